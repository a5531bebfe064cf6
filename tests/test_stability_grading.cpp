// Study (i), non-uniform meshes (docs/stability.md, docs/graded.md#safe-gradings): on the clamped
// box under a Kelvin load (tests/support/studies/grading_setup.hpp, exact solution known), refining
// one half red-green but not the clamped face makes constant elements worse than no refinement,
// refining the clamped face with it does not; grading_rule_warning tells the two apart on both
// sides of kMaxSupportSizeRatio, and the graded remesher meshes a supported region as finely as
// the operating region.
#include <catch2/catch.hpp>

#include "bemsurg/meshing/graded_remesher.hpp"
#include "support/skip.hpp"
#include "support/studies/grading_setup.hpp"

using namespace bemsurg;
using namespace bemsurg::bench::grading;

TEST_CASE("grading rule: a half refined without its clamped face is worse and warned about, with it neither", "[stability][grading]") {
  const TriangleMesh half = refined_box(2, Zone::HalfMinus, 1), rule = refined_box(2, Zone::HalfMinusAndSupported, 1);
  REQUIRE(kMaxSupportSizeRatio == 1.2);  // issue 37: the largest ratio study (i) measured safe was 1.19
  const GradingResult base = solve_constant(base_box(2)), bad = solve_constant(half), good = solve_constant(rule);
  INFO("base " << base.displacement_error << ", half only " << bad.displacement_error << " (ratio " << bad.support_ratio
               << "), half + supported " << good.displacement_error << " (ratio " << good.support_ratio << ")");
  // Outside the limit: the method, not a bug, makes the error worse than the unrefined mesh's
  // (measured 15.5 % against 5.5 %), and the rule's warning names the ratio and the limit.
  CHECK(bad.support_ratio > kMaxSupportSizeRatio);
  CHECK(bad.displacement_error > 2.0 * base.displacement_error);
  const std::string warning = grading_rule_warning(half, held(half));
  CHECK_THAT(warning, Catch::Contains("1.78 times") && Catch::Contains("limit " + number_text(kMaxSupportSizeRatio)));
  // Inside: no warning, and the error is within the uniform meshes' band (measured 8.9 %; uniform
  // 252 and 448 elements: 9.9 % and 7.4 %), well below the rule-breaking mesh's.
  CHECK(good.support_ratio <= kMaxSupportSizeRatio);
  CHECK(grading_rule_warning(rule, held(rule)).empty());
  CHECK(good.displacement_error < 0.1);
  CHECK(good.displacement_error < 0.65 * bad.displacement_error);
}

TEST_CASE("grading rule: the graded remesher refines a supported region like the operating region", "[stability][grading]") {
  testing::skip_unless(graded_remesher_available(), "this build has no remesher (BEMSURG_WITH_REMESHER=OFF)");
  const TriangleMesh free_support = graded_box(0.25, 0.5, false), rule = graded_box(0.25, 0.5, true);
  const double r_free = support_size_ratio(free_support, held(free_support)), r_rule = support_size_ratio(rule, held(rule));
  INFO("support size ratio: region only " << r_free << ", region + supported " << r_rule);
  CHECK(r_rule <= kMaxSupportSizeRatio);
  CHECK(grading_rule_warning(rule, held(rule)).empty());
  CHECK(r_free > kMaxSupportSizeRatio);
  CHECK_THAT(grading_rule_warning(free_support, held(free_support)), Catch::Contains("operating_region.supported"));
  // The size field itself: inside length on the held face however far from the region.
  GradedRemeshOptions o;
  o.inside_edge_length = 0.25;
  o.outside_edge_length = 0.5;
  o.growth = 2.0;
  o.supported_regions.push_back(OperatingRegion::box(Vec3(-1, -1, kTop - 0.01), Vec3(1, 1, kTop + 1)));
  const OperatingRegion half = OperatingRegion::box(Vec3(-1, -1, -1), Vec3(0, 1, kTop + 1));
  CHECK(graded_target_size(half, o, Vec3(0.5, 0.5, kTop)) == 0.25);
  CHECK(graded_target_size(half, o, Vec3(0.5, 0.5, 1.0)) == 0.5);
}
