// grading_studies.cpp: study (i) of issue 25, non-uniform meshes (docs/graded.md, docs/stability.md).
// The clamped-box Kelvin problem of grading_setup.hpp on uniform boxes, on boxes refined red-green
// (one half, the mirror half, both, the supported face, a half with the supported face; 1-3
// levels) and on graded Gmsh meshes: error against element count per strategy
// (stability_i_strategies.csv), and, for graded meshes fine in one half, error against how much
// coarser the held face is than the finest elements, with and without the safe-grading rule
// (stability_i_ratio.csv). One row per mesh and element type: "constant" today; linear elements
// (issue 27) are one more solver call on the same meshes, one more value of element_type.
#include <algorithm>
#include <cmath>

#include "stability_study.hpp"
#include "support/studies/grading_setup.hpp"

namespace bemsurg::bench::stability {
namespace {

using namespace grading;

const Zone kZones[] = {Zone::HalfMinus,           Zone::HalfPlus, Zone::Both, Zone::Supported, Zone::HalfMinusAndSupported,
                       Zone::HalfPlusAndSupported};

struct RatioPoint {
  double outside = 0.0;
  GradingResult free_support, rule;
};

/// The threshold: the largest support size ratio of the rule-breaking graded meshes whose
/// displacement error stays within 10 % of the rule-following mesh of the same sizes.
double safe_support_ratio(const std::vector<RatioPoint>& points) {
  double safe = 1.0;
  for (const RatioPoint& p : points) {
    if (p.free_support.displacement_error > 1.1 * p.rule.displacement_error) break;
    safe = std::max(safe, p.free_support.support_ratio);
  }
  return safe;
}

}  // namespace

nlohmann::json study_grading(const StudyContext& ctx) {
  const std::vector<int> uniform = ctx.quick ? std::vector<int>{2, 3, 4} : std::vector<int>{2, 3, 4, 5, 6, 8};
  const int max_level = ctx.quick ? 1 : 3;
  // Dense BEM: a 4,000-element mesh takes a minute to factorise on two cores; the full sweep stops
  // each strategy's levels before that.
  const Index max_elements = 2000;
  CsvTable strategies(ctx.csv_dir / "stability_i_strategies.csv",
                      {"strategy", "element_type", "base_divisions", "level", "elements", "max_neighbour_size_ratio", "support_size_ratio",
                       "displacement_error", "traction_error"});
  std::vector<std::pair<std::string, GradingResult>> found;
  const auto record = [&](const std::string& strategy, int base, int level, const TriangleMesh& mesh) {
    const GradingResult r = solve_constant(mesh);
    strategies.row({strategy, std::string("constant"), double(base), double(level), double(r.elements), r.max_ratio, r.support_ratio,
                    r.displacement_error, r.traction_error});
    found.emplace_back(strategy + " n" + std::to_string(base) + (level > 0 ? " L" + std::to_string(level) : std::string()), r);
    return r;
  };
  for (int n : uniform) record("uniform", n, 0, base_box(n));
  for (Zone z : kZones)
    for (int level = 1; level <= max_level; ++level) {
      const TriangleMesh mesh = refined_box(2, z, level);
      if (mesh.num_elements() <= max_elements) record(std::string("red-green ") + zone_name(z), 2, level, mesh);
    }
  // An odd base (3 x 3 x 9) is not mirror-symmetric in x: the two halves differ (the case).
  if (!ctx.quick)
    for (Zone z : {Zone::HalfMinus, Zone::HalfPlus}) record(std::string("red-green ") + zone_name(z), 3, 1, refined_box(3, z, 1));

  CsvTable ratio_csv(ctx.csv_dir / "stability_i_ratio.csv",
                     {"outside_edge_length", "element_type", "rule", "elements", "max_neighbour_size_ratio", "support_size_ratio",
                      "displacement_error", "traction_error"});
  std::vector<RatioPoint> points;
  const double inside = 0.25;
  if (graded_remesher_available()) {
    const std::vector<double> outs = ctx.quick ? std::vector<double>{0.25, 0.5} : std::vector<double>{0.25, 0.3, 0.375, 0.5, 0.625, 0.75};
    for (double out : outs) {
      RatioPoint p{out, solve_constant(graded_box(inside, out, false)), solve_constant(graded_box(inside, out, true))};
      for (const auto& [rule, r] :
           {std::pair<const char*, const GradingResult&>{"operating region only", p.free_support}, {"region + supported", p.rule}})
        ratio_csv.row({out, std::string("constant"), std::string(rule), double(r.elements), r.max_ratio, r.support_ratio,
                       r.displacement_error, r.traction_error});
      points.push_back(p);
    }
  }

  const auto error_of = [&](const std::string& name) {
    for (const auto& [n, r] : found)
      if (n == name) return r.displacement_error;
    return std::nan("");
  };
  nlohmann::json out;
  out["parameter"] = "refinement strategy (uniform, red-green, graded) and the support size ratio: largest held element / smallest element";
  out["csv"] = {"stability_i_strategies.csv", "stability_i_ratio.csv"};
  out["base_error"] = error_of("uniform n2");  // the base of the red-green meshes
  out["half_error"] = error_of("red-green half x<0 n2 L1");
  out["mirror_half_error"] = error_of("red-green half x>0 n2 L1");
  out["half_and_supported_error"] = error_of("red-green half x<0 + supported n2 L1");
  out["both_error"] = error_of("red-green both halves n2 L1");
  if (!ctx.quick) {
    out["odd_base_error"] = error_of("uniform n3");
    out["odd_half_error"] = error_of("red-green half x<0 n3 L1");
    out["odd_mirror_half_error"] = error_of("red-green half x>0 n3 L1");
  }
  out["limit"] = kMaxSupportSizeRatio;
  if (!points.empty()) {
    const double safe = safe_support_ratio(points);
    out["threshold"] = safe;
    out["threshold_text"] =
        "graded meshes fine in one half stayed within 10 % of the rule-following mesh's displacement error up to a support size ratio of " +
        number_text(std::round(100.0 * safe) / 100.0) + "; bemsurg's limit is " + number_text(kMaxSupportSizeRatio);
  } else {
    out["threshold"] = kMaxSupportSizeRatio;
    out["threshold_text"] =
        "no remesher in this build: the graded sweep was not run; bemsurg's limit is " + number_text(kMaxSupportSizeRatio);
  }
  out["behaviour"] =
      "the graded remesher refines the supported region with the operating region when asked (GradedRemeshOptions::supported_regions, "
      "scene key operating_region.supported), and grading_rule_warning (mesh/graded_remesher.hpp) warns when held elements are more "
      "than kMaxSupportSizeRatio times the finest";
  return out;
}

}  // namespace bemsurg::bench::stability
