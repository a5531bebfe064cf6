// test_stability_geometry.cpp: the thresholds of stability studies (b) interior points approaching
// the surface and (c) sliver triangles (issue 25, docs/stability.md), each asserted on both sides.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>

#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "support/studies/geometry_setup.hpp"

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

TEST_CASE("interior stress is refused closer than kMinStressClearanceFraction x h, displacement is evaluated down to its own limit",
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

namespace {
/// The slab width eps that gives the needle box's needles (legs eps and 0.6) the aspect ratio r:
/// the small root of (sqrt(3)/2) (0.36 + eps^2) / (0.6 eps) = r.
double needle_eps(double r) {
  const double b = 1.2 * r / std::sqrt(3.0);
  return 0.5 * (b - std::sqrt(b * b - 4.0 * 0.36));
}

/// Relative L2 traction error of the Kelvin problem solved on `mesh` (displacement held below z = 0).
double traction_error(const TriangleMesh& mesh) {
  const KelvinBox kb;
  return solve_exact_trace_problem(mesh, kb.m, kb.field, [&](Index e) { return mesh.centroid(e).z() < 0.0; }).traction;
}
}  // namespace

TEST_CASE("sliver triangles: warned about above kSliverWarningAspectRatio, refused above kMaxAspectRatio", "[stability][sliver]") {
  using bench::stability::needle_box;
  REQUIRE(kSliverWarningAspectRatio == 40.0);  // issue 37: where study (c) measured the error doubling
  // The measure: 1 for an equilateral triangle; a right triangle of legs 1 and eps: (sqrt(3)/2)(1 + eps^2)/eps.
  CHECK(aspect_ratio(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(0.75), 0)) == Approx(1.0).epsilon(1e-14));
  CHECK(aspect_ratio(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1e-3, 0)) == Approx(0.5 * std::sqrt(3.0) * (1 + 1e-6) / 1e-3).epsilon(1e-12));

  // Both sides of the warning: 0.95 and 1.05 x kSliverWarningAspectRatio.
  const TriangleMesh below = needle_box(1, needle_eps(0.95 * kSliverWarningAspectRatio));
  const TriangleMesh above = needle_box(1, needle_eps(1.05 * kSliverWarningAspectRatio));
  CHECK(worst_aspect_ratio(above).ratio == Approx(1.05 * kSliverWarningAspectRatio).epsilon(1e-9));
  CHECK(sliver_warning(below).empty());
  const std::string w = sliver_warning(above);
  CHECK_THAT(w, Catch::Contains("element " + std::to_string(worst_aspect_ratio(above).element) + " has aspect ratio 42") &&
                    Catch::Contains("above 40") && Catch::Contains("16 elements"));

  // Why: the traction error of the Kelvin box (0.162 with the widest slab, measured) has nearly
  // doubled there (measured 0.316 at 42, 1.95x; 0.456 at 105) while at 20, the cutter's walls, it
  // is 0.251 (1.55x; bound 1.7x).
  const double base = traction_error(needle_box(1, 0.25));
  const double at_20 = traction_error(needle_box(1, needle_eps(20.0)));
  const double at_warning = traction_error(above);
  INFO("traction error: " << base << " without slivers, " << at_20 << " at 20, " << at_warning << " above the warning");
  CHECK(at_20 < 1.7 * base);
  CHECK(at_warning > 1.8 * base);
  CHECK(at_warning > 1.2 * at_20);

  // Both sides of the refusal: 0.9 and 1.1 x kMaxAspectRatio.
  CHECK_NOTHROW(require_valid_mesh(needle_box(1, needle_eps(0.9 * kMaxAspectRatio))));
  const TriangleMesh refused = needle_box(1, needle_eps(1.1 * kMaxAspectRatio));
  CHECK_THROWS_AS(require_valid_mesh(refused), InvalidMeshError);
  CHECK_THROWS_WITH(require_valid_mesh(refused), Catch::Contains("face " + std::to_string(worst_aspect_ratio(refused).element)) &&
                                                     Catch::Contains("sliver of aspect ratio 11000") && Catch::Contains("limit 10000"));
}

TEST_CASE("bemsurg's own cuts stay below the sliver warning", "[stability][sliver]") {
  // The cutter's narrowest gap (kMinimumGapRatio x the edge) makes its thinnest walls: measured
  // aspect ratio 19.4 on an 8^3 box after these four steps and a deepening (also after six steps
  // and two deepenings); the warning is at 100.
  const auto mesh = std::make_shared<const TriangleMesh>(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 8, 8, 8));
  SurfaceCutter cutter(mesh, {});
  for (int k = 0; k < 4; ++k) REQUIRE(cutter.step(Vec3(0.31, 0.5, 1.02), Vec3(1, 0.1, 0)).accepted);
  REQUIRE(cutter.deepen().accepted);
  const WorstAspectRatio worst = worst_aspect_ratio(*cutter.mesh());
  INFO("worst aspect ratio after the cut " << worst.ratio);
  CHECK(worst.ratio > 5.0);  // the cut did make thin walls
  CHECK(sliver_warning(*cutter.mesh()).empty());
  CHECK_NOTHROW(require_valid_mesh(*cutter.mesh()));
}
