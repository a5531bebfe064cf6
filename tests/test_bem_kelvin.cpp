// Kelvin point force outside a box (docs/design.md §8): the exact field's traces are prescribed on the
// box (u at centroids, sigma(centroid) . n), the BEM solves for the rest; Dirichlet, Neumann and
// mixed problems, each with error bounds and observed orders of convergence between two meshes
// (h = 0.3 and 0.2), asserted separately for the row of elements along the box's edges and for
// the rest (tests/support/convergence.hpp). The coarsest box (h = 0.6) is all edge row.
//
// Measured orders at h = 0.3 -> 0.2 (OMP, Release) are in each case; bounds on errors are ~1.3x
// the finer mesh's measured error and bounds on orders ~0.75x the measured order. Where the
// measured order is below 0.3 the error does not fall usefully under refinement: that is stated,
// and only the error bound is asserted.
#include <catch2/catch.hpp>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "support/convergence.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;
using bemsurg_test::observed_order;
using bemsurg_test::solve_split;
using bemsurg_test::SplitErrors;

namespace {
const Material kKelvinMaterial{1.0, 0.3, 0.0};
const ElasticField kKelvinField = kelvin_field(kKelvinMaterial, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
TriangleMesh box(int n) { return box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n); }
const double kHCoarse = 0.3, kHFine = 0.2;  // box(2), box(3)

template <class Held>
std::pair<SplitErrors, SplitErrors> two_levels(Held held) {
  const TriangleMesh c = box(2), f = box(3);
  return {solve_split(c, kKelvinMaterial, kKelvinField, held(c)), solve_split(f, kKelvinMaterial, kKelvinField, held(f))};
}
double order(double coarse, double fine) { return observed_order(coarse, fine, kHCoarse, kHFine); }
}  // namespace

TEST_CASE("Kelvin, Dirichlet: tractions from prescribed displacements") {
  const auto [c, f] = two_levels([](const TriangleMesh&) { return [](Index) { return true; }; });
  INFO("traction: all " << c.all.traction << " -> " << f.all.traction << ", edge row " << c.edge.traction << " -> " << f.edge.traction
                        << ", rest " << c.rest.traction << " -> " << f.rest.traction);
  // Measured: rest 4.24e-2 -> 3.67e-2 (order 0.36); edge row 0.112 -> 0.119 (order -0.16: the
  // edge row's traction does not converge); all 8.42e-2 -> 7.33e-2 (0.34).
  CHECK(order(c.rest.traction, f.rest.traction) > 0.27);
  CHECK(f.rest.traction < 0.048);
  CHECK(f.edge.traction < 0.155);
  CHECK(f.all.traction < 0.095);
}

TEST_CASE("Kelvin, Neumann: displacements from prescribed tractions (four elements fix rigid motion)") {
  const auto [c, f] = two_levels([](const TriangleMesh& m) { return a_few_elements(m); });
  INFO("displacement: all " << c.all.displacement << " -> " << f.all.displacement << ", edge row " << c.edge.displacement << " -> "
                            << f.edge.displacement << ", rest " << c.rest.displacement << " -> " << f.rest.displacement);
  // Measured: all 5.79e-2 -> 5.39e-2 (order 0.18), edge row 6.58e-2 -> 6.36e-2 (0.08), rest
  // 4.09e-2 -> 4.46e-2 (-0.21): on this box the Neumann displacement stagnates at ~5 % from
  // h = 0.3 on (h = 0.15 gives 4.4 %; pinning the six face-centre elements instead gives the same
  // picture), so no order is asserted between these two meshes, only the errors. From h = 0.6
  // (all edge row) to 0.3 the error falls with order 1.11 (12.5 % -> 5.8 %); asserted > 0.83.
  const TriangleMesh coarsest = box(1);
  const SplitErrors c0 = solve_split(coarsest, kKelvinMaterial, kKelvinField, a_few_elements(coarsest));
  INFO("h = 0.6: all " << c0.all.displacement);
  CHECK(observed_order(c0.all.displacement, c.all.displacement, 0.6, kHCoarse) > 0.83);
  CHECK(f.all.displacement < 0.07);
  CHECK(f.edge.displacement < 0.083);
  CHECK(f.rest.displacement < 0.058);
}

TEST_CASE("Kelvin, mixed: lower half held, upper half loaded") {
  const auto [c, f] = two_levels([](const TriangleMesh& m) { return [&m](Index e) { return m.centroid(e).z() < 0.0; }; });
  INFO("u: all " << c.all.displacement << " -> " << f.all.displacement << ", edge row " << c.edge.displacement << " -> "
                 << f.edge.displacement << ", rest " << c.rest.displacement << " -> " << f.rest.displacement);
  INFO("t: all " << c.all.traction << " -> " << f.all.traction << ", edge row " << c.edge.traction << " -> " << f.edge.traction << ", rest "
                 << c.rest.traction << " -> " << f.rest.traction);
  // Measured u: rest 1.56e-2 -> 1.10e-2 (order 0.88), edge row 3.38e-2 -> 2.44e-2 (0.81),
  // all 2.85e-2 -> 1.82e-2 (1.11). t: rest 6.41e-2 -> 4.90e-2 (0.66), edge row 0.108 -> 0.106
  // (0.03: not converging), all 9.22e-2 -> 7.72e-2 (0.44).
  CHECK(order(c.rest.displacement, f.rest.displacement) > 0.66);
  CHECK(order(c.edge.displacement, f.edge.displacement) > 0.6);
  CHECK(order(c.rest.traction, f.rest.traction) > 0.5);
  CHECK(f.rest.displacement < 0.0143);
  CHECK(f.edge.displacement < 0.032);
  CHECK(f.rest.traction < 0.064);
  CHECK(f.edge.traction < 0.138);
}
