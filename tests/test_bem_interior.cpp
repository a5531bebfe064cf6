// Interior displacement and stress (Somigliana's identity and its gradient) for the Kelvin and
// Lamé problems, with the boundary values the BEM computed; error bounds and observed orders of
// convergence.
#include <catch2/catch.hpp>

#include <cmath>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
/// Solves the exact-trace problem of `field` (displacement where `held`), then the relative errors
/// of interior displacement and stress at `points` (verification::interior_relative_errors).
InteriorErrors interior_errors(const TriangleMesh& mesh, const Material& m, const ElasticField& field,
                               const std::function<bool(Index)>& held, const RowMatrixX3d& points,
                               const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero()) {
  BoundarySolution s;
  solve_exact_trace_problem(mesh, m, field, held, gravity, &s);
  return interior_relative_errors(mesh, m, field, s, points, gravity);
}
}  // namespace

TEST_CASE("interior displacement and stress of the Kelvin field in a box") {
  const Material m{1.0, 0.3, 0.0};
  const ElasticField field = kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
  RowMatrixX3d points(4, 3);
  points << 0.0, 0.0, 0.0, 0.5, -0.2, 0.1, -0.4, 0.3, -0.2, 0.2, 0.1, 0.3;
  std::vector<InteriorErrors> e;
  for (int n : {1, 2}) {
    const TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n);
    e.push_back(interior_errors(box, m, field, [&](Index k) { return box.centroid(k).z() < 0.0; }, points));
  }
  INFO("u: " << e[0].displacement << " -> " << e[1].displacement << ", stress: " << e[0].stress << " -> " << e[1].stress);
  // h halves. Measured: u 2.97e-2 -> 6.26e-3 (order 2.24), stress 0.104 -> 3.38e-2 (1.63).
  // Bounds: orders ~0.75x, errors ~1.3x the measured.
  CHECK(std::log2(e[0].displacement / e[1].displacement) > 1.7);
  CHECK(std::log2(e[0].stress / e[1].stress) > 1.2);
  CHECK(e[1].displacement < 0.0082);
  CHECK(e[1].stress < 0.044);
}

TEST_CASE("interior displacement and stress of the Lamé sphere") {
  const Material m{1.0, 0.3, 0.0};
  const ElasticField field = lame_field(m, Eigen::Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0);
  RowMatrixX3d points(3, 3);
  points << 1.5, 0.0, 0.0, 0.0, -1.2, 0.9, 0.8, 0.8, 0.8;
  std::vector<InteriorErrors> e;
  for (int s : {1, 2}) {
    const TriangleMesh shell = hollow_sphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2.0, s, s);
    e.push_back(interior_errors(shell, m, field, [&](Index k) { return shell.centroid(k).norm() < 1.5; }, points));
  }
  INFO("u: " << e[0].displacement << " -> " << e[1].displacement << ", stress: " << e[0].stress << " -> " << e[1].stress);
  // h halves. Measured: u 2.14e-2 -> 1.40e-2 (order 0.61), stress 0.109 -> 2.79e-2 (1.96).
  // Bounds: orders ~0.75x, errors ~1.3x the measured.
  CHECK(std::log2(e[0].displacement / e[1].displacement) > 0.45);
  CHECK(std::log2(e[0].stress / e[1].stress) > 1.45);
  CHECK(e[1].displacement < 0.0182);
  CHECK(e[1].stress < 0.0363);
}

TEST_CASE("interior points of the hanging bar include the gravity term") {
  const Material m{1.0, 0.3, 1.0};
  const ElasticField field = hanging_bar_field(m, 1.0, 3.0);
  RowMatrixX3d points(3, 3);
  points << 0.0, 0.0, 1.5, 0.2, -0.1, 0.8, -0.2, 0.2, 2.2;
  const TriangleMesh bar = box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, 3.0), 2, 2, 6);
  const InteriorErrors e = interior_errors(bar, m, field, [&](Index k) { return bar.centroid(k).z() > 3.0 - 1e-9; }, points,
                                           Eigen::Vector3d(0, 0, -1.0));
  INFO("u: " << e.displacement << ", stress: " << e.stress);
  // Measured: u 1.21e-2, stress 4.84e-2; bounds ~1.3x. (Without the gravity term: see
  // test_bem_gravity.)
  CHECK(e.displacement < 0.0157);
  CHECK(e.stress < 0.063);
}
