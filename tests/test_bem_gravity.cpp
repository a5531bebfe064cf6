// Self-weight moved to the surface (kernel P, docs/design.md §3): a bar hanging under its own weight,
// and a solid under uniform pressure (no gravity), both against closed forms, with error bounds
// (~1.3x the measured error on the finer mesh) and observed orders of convergence (bounds ~0.75x
// the measured order), asserted separately for the row of elements along the box's edges and the
// rest (tests/support/convergence.hpp).
#include <catch2/catch.hpp>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "support/convergence.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
const Material kMaterial{1.0, 0.3, 1.0};
const double kL = 3.0, kG = 1.0;
const ElasticField kBar = hanging_bar_field(kMaterial, kG, kL);
TriangleMesh bar(int n) { return box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, kL), n, n, 3 * n); }
}  // namespace

TEST_CASE("hanging bar: held at the top, sagging under gravity") {
  // n = 1 pins only two points (a rotation stays free) and at n = 2 every element touches an edge,
  // so the orders come from n = 4 and 6 (h = 1/4, 1/6).
  std::vector<bemsurg_test::SplitErrors> e;
  for (int n : {4, 6}) {
    const TriangleMesh m = bar(n);
    e.push_back(bemsurg_test::solve_split(
        m, kMaterial, kBar, [&](Index k) { return m.centroid(k).z() > kL - 1e-9; }, Eigen::Vector3d(0, 0, -kG)));
  }
  auto order = [](double c, double f) { return bemsurg_test::observed_order(c, f, 1.0 / 4, 1.0 / 6); };
  INFO("u: all " << e[0].all.displacement << " -> " << e[1].all.displacement << ", edge row " << e[0].edge.displacement << " -> "
                 << e[1].edge.displacement << ", rest " << e[0].rest.displacement << " -> " << e[1].rest.displacement);
  INFO("t: all " << e[0].all.traction << " -> " << e[1].all.traction << ", edge row " << e[0].edge.traction << " -> " << e[1].edge.traction
                 << ", rest " << e[0].rest.traction << " -> " << e[1].rest.traction);
  // Measured u: rest 7.29e-3 -> 5.01e-3 (order 0.92), edge row 8.62e-3 -> 5.97e-3 (0.90).
  // t (the held top face): rest 1.19e-2 -> 8.68e-3 (0.77), edge row 3.23e-2 -> 2.95e-2 (0.22:
  // hardly converging).
  CHECK(order(e[0].rest.displacement, e[1].rest.displacement) > 0.7);
  CHECK(order(e[0].edge.displacement, e[1].edge.displacement) > 0.68);
  CHECK(order(e[0].rest.traction, e[1].rest.traction) > 0.58);
  CHECK(e[1].rest.displacement < 0.0065);
  CHECK(e[1].edge.displacement < 0.0078);
  CHECK(e[1].rest.traction < 0.0113);
  CHECK(e[1].edge.traction < 0.038);
}

TEST_CASE("hanging bar without the gravity term is far off (the term is what carries the load)") {
  const TriangleMesh m = bar(2);
  const RelativeErrors e = solve_exact_trace_problem(m, kMaterial, kBar, [&](Index k) { return m.centroid(k).z() > kL - 1e-9; });
  CHECK(e.displacement > 0.5);  // measured 0.99: without the term the solution hardly moves
}

TEST_CASE("solid cube under uniform pressure: u = -p (1 - 2 nu) x / E") {
  const ElasticField field = uniform_pressure_field(kMaterial, 1.0);
  std::vector<bemsurg_test::SplitErrors> e;
  for (int n : {4, 6}) {  // at n = 2 every element touches an edge
    const TriangleMesh m = box_mesh(Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.5, 0.5, 0.5), n, n, n);
    e.push_back(bemsurg_test::solve_split(m, kMaterial, field, a_few_elements(m)));
  }
  auto order = [](double c, double f) { return bemsurg_test::observed_order(c, f, 1.0 / 4, 1.0 / 6); };
  INFO("u: all " << e[0].all.displacement << " -> " << e[1].all.displacement << ", edge row " << e[0].edge.displacement << " -> "
                 << e[1].edge.displacement << ", rest " << e[0].rest.displacement << " -> " << e[1].rest.displacement);
  // Measured: rest 3.98e-2 -> 1.93e-2 (order 1.79), edge row 4.07e-2 -> 2.39e-2 (1.31). (The four
  // elements that fix the rigid motion move with n; at n = 8 the error is 2.1 %, order 0.2 from
  // n = 6, so the order holds for these two meshes, not as a trend.)
  CHECK(order(e[0].rest.displacement, e[1].rest.displacement) > 1.35);
  CHECK(order(e[0].edge.displacement, e[1].edge.displacement) > 1.0);
  CHECK(e[1].rest.displacement < 0.025);
  CHECK(e[1].edge.displacement < 0.031);
}
