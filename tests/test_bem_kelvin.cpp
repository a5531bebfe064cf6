// Kelvin point force outside a box (DESIGN.md §8): the exact field's traces are prescribed on the
// box (u at centroids, sigma(centroid) . n), the BEM solves for the rest; Dirichlet, Neumann and
// mixed problems, each with an error bound and an error that falls under refinement.
#include <catch2/catch.hpp>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
const Material kMaterial{1.0, 0.3, 0.0};
const ElasticField kField = kelvin_field(kMaterial, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
TriangleMesh box(int n) { return box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n); }
}  // namespace

TEST_CASE("Kelvin, Dirichlet: tractions from prescribed displacements") {
  const RelativeErrors coarse = solve_exact_trace_problem(box(1), kMaterial, kField, [](Index) { return true; });
  const RelativeErrors fine = solve_exact_trace_problem(box(2), kMaterial, kField, [](Index) { return true; });
  INFO("traction error: " << coarse.traction << " -> " << fine.traction);
  CHECK(fine.traction < 0.8 * coarse.traction);
  CHECK(fine.traction < 0.10);
}

TEST_CASE("Kelvin, Neumann: displacements from prescribed tractions (four elements fix rigid motion)") {
  const TriangleMesh c = box(1), f = box(2);
  const RelativeErrors coarse = solve_exact_trace_problem(c, kMaterial, kField, a_few_elements(c));
  const RelativeErrors fine = solve_exact_trace_problem(f, kMaterial, kField, a_few_elements(f));
  INFO("displacement error: " << coarse.displacement << " -> " << fine.displacement);
  CHECK(fine.displacement < 0.8 * coarse.displacement);
  CHECK(fine.displacement < 0.07);
}

TEST_CASE("Kelvin, mixed: lower half held, upper half loaded") {
  const TriangleMesh c = box(1), f = box(2);
  auto lower = [](const TriangleMesh& m) { return [&m](Index e) { return m.centroid(e).z() < 0.0; }; };
  const RelativeErrors coarse = solve_exact_trace_problem(c, kMaterial, kField, lower(c));
  const RelativeErrors fine = solve_exact_trace_problem(f, kMaterial, kField, lower(f));
  INFO("u: " << coarse.displacement << " -> " << fine.displacement << ", t: " << coarse.traction << " -> " << fine.traction);
  CHECK(fine.displacement < 0.8 * coarse.displacement);
  CHECK(fine.traction < 0.9 * coarse.traction);
  CHECK(fine.displacement < 0.04);
  CHECK(fine.traction < 0.12);
}
