// test_stability_geometry.cpp: the thresholds of stability studies (b) interior points approaching
// the surface and (c) sliver triangles (issue 25, docs/stability.md), each asserted on both sides.
#include <catch2/catch.hpp>

#include <cmath>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
/// The Kelvin box of bench_stability --study interior (coarse: 64 elements), solved once.
struct KelvinBox {
  Material m{1.0, 0.3, 0.0};
  ElasticField field = kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
  TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3, 2, 2);
  BoundarySolution solved;
  KelvinBox() {
    solve_exact_trace_problem(
        box, m, field, [&](Index e) { return box.centroid(e).z() < 0.0; }, Eigen::Vector3d::Zero(), &solved);
  }
  /// Relative errors of u and stress at one point.
  std::pair<double, double> errors(const InteriorEvaluator& ev, const Eigen::Vector3d& x, bool with_stress = true) const {
    RowMatrixX3d p(1, 3);
    p.row(0) = x.transpose();
    const double eu = (ev.displacement(p, solved).row(0).transpose() - field.displacement(x)).norm() / field.displacement(x).norm();
    if (!with_stress) return {eu, 0.0};
    const Eigen::Matrix3d S = field.stress(x);
    Eigen::Matrix<double, 1, 6> exact;
    exact << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
    return {eu, (ev.stress(p, solved).row(0) - exact).norm() / exact.norm()};
  }
};
}  // namespace

TEST_CASE("interior stress is refused closer than kMinStressClearanceFraction x h; displacement is evaluated down to its own limit",
          "[stability][interior]") {
  const KelvinBox kb;
  const InteriorEvaluator ev(kb.box, kb.m);
  // The top-face vertex (0.333, 0, 0.6) is shared by six elements of longest edge h = 0.897 (the
  // cell diagonal): the worst place for stress (its error grows like h / d there).
  const double h = std::hypot(2.0 / 3.0, 0.6);
  const Eigen::Vector3d vertex(1.0 / 3.0, 0.0, 0.6), down(0.0, 0.0, -1.0);
  const double ls = kMinStressClearanceFraction, lu = min_clearance_fraction(QuadratureOptions());
  REQUIRE(min_stress_clearance_fraction(QuadratureOptions()) == ls);

  // Far (d = h) and just outside the stress limit (1.1 x 0.25 h): evaluated. Measured stress error
  // 8.6e-2 at h and 0.24 at 1.1 x the limit; bounds ~1.25x. The 20 % the limit is set at is for the
  // converged mesh of the full sweep; this coarse mesh is a little worse.
  const auto far = kb.errors(ev, vertex + h * down);
  const auto inside = kb.errors(ev, vertex + 1.1 * ls * h * down);
  INFO("stress error at h " << far.second << ", at 1.1 x the stress limit " << inside.second);
  CHECK(far.second < 0.11);
  CHECK(inside.second < 0.3);

  // Just inside the stress limit (0.9 x): stress refused, naming the point, the limit and what to do;
  // displacement still evaluated, within a few per cent. Measured u error 5.2e-2; bound 0.07.
  InteriorEvaluator unchecked(kb.box, kb.m);  // the refusal switched off, for the band's figures
  unchecked.allow_points_too_close_for_studies(true);
  const Eigen::Vector3d band = vertex + 0.9 * ls * h * down;
  RowMatrixX3d p(1, 3);
  p.row(0) = band.transpose();
  CHECK_THROWS_AS(ev.stress(p, kb.solved), InvalidArgumentError);
  CHECK_THROWS_WITH(ev.stress(p, kb.solved),
                    Catch::Contains("stress: point 0") && Catch::Contains("closer than 0.25") && Catch::Contains("refine the mesh"));
  INFO("u error in the band " << kb.errors(ev, band, false).first << ", stress at 0.01 h "
                              << kb.errors(unchecked, vertex + 0.01 * h * down).second << ", u at 1.1 x the u limit "
                              << kb.errors(ev, vertex + 1.1 * lu * h * down, false).first);
  CHECK(kb.errors(ev, band, false).first < 0.07);

  // Why: with the refusal switched off, the band below the limit is silently wrong: at 0.01 h the
  // stress error is several times the stress itself (measured 5.3), with the exact quadrature too.
  CHECK(kb.errors(unchecked, vertex + 0.01 * h * down).second > 1.0);

  // The displacement limit on both sides: 1.1 x evaluated (measured u error 0.13 at the vertex,
  // bound 0.17), 0.9 x refused naming the quadrature's limit.
  CHECK(kb.errors(ev, vertex + 1.1 * lu * h * down, false).first < 0.17);
  p.row(0) = (vertex + 0.9 * lu * h * down).transpose();
  CHECK_THROWS_WITH(ev.displacement(p, kb.solved), Catch::Contains("displacement: point 0") && Catch::Contains("closer than 0.00293"));
}
