// Self-weight moved to the surface (kernel P, DESIGN.md §3): a bar hanging under its own weight,
// and a solid under uniform pressure (no gravity), both against closed forms.
#include <catch2/catch.hpp>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
const Material kMaterial{1.0, 0.3, 1.0};
const double kL = 3.0, kG = 1.0;
const ElasticField kBar = hanging_bar_field(kMaterial, kG, kL);
TriangleMesh bar(int n) { return box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, kL), n, n, 3 * n); }
}  // namespace

TEST_CASE("hanging bar: held at the top, sagging under gravity") {
  std::vector<RelativeErrors> e;
  for (int n : {2, 4}) {  // n = 1 pins only two points: a rotation stays free
    const TriangleMesh m = bar(n);
    e.push_back(solve_exact_trace_problem(m, kMaterial, kBar, [&](Index k) { return m.centroid(k).z() > kL - 1e-9; },
                                          Eigen::Vector3d(0, 0, -kG)));
  }
  INFO("u: " << e[0].displacement << " -> " << e[1].displacement << ", t: " << e[0].traction << " -> " << e[1].traction);
  CHECK(e[1].displacement < 0.7 * e[0].displacement);
  CHECK(e[1].displacement < 0.012);
  CHECK(e[1].traction < 0.04);
}

TEST_CASE("hanging bar without the gravity term is far off (the term is what carries the load)") {
  const TriangleMesh m = bar(2);
  const RelativeErrors e = solve_exact_trace_problem(m, kMaterial, kBar, [&](Index k) { return m.centroid(k).z() > kL - 1e-9; });
  CHECK(e.displacement > 0.5);
}

TEST_CASE("solid cube under uniform pressure: u = -p (1 - 2 nu) x / E") {
  const ElasticField field = uniform_pressure_field(kMaterial, 1.0);
  std::vector<RelativeErrors> e;
  for (int n : {2, 4}) {
    const TriangleMesh m = box_mesh(Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.5, 0.5, 0.5), n, n, n);
    e.push_back(solve_exact_trace_problem(m, kMaterial, field, a_few_elements(m)));
  }
  INFO("u: " << e[0].displacement << " -> " << e[1].displacement);
  CHECK(e[1].displacement < 0.7 * e[0].displacement);
  CHECK(e[1].displacement < 0.055);
}
