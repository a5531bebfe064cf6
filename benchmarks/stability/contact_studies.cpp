// contact_studies.cpp: stability studies (g) thin parts and tool size against element size and (h)
// press depth against tool radius (issue 25, docs/stability.md; the runs: tests/support/studies/contact_setup.hpp).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "bemsurg/timing.hpp"
#include "stability_study.hpp"
#include "support/studies/contact_setup.hpp"

namespace bemsurg::bench::stability {
namespace {

/// The first swept value (walking from the resolved end towards the unresolved one) whose error
/// exceeds `limit`, interpolated in log x between it and its predecessor; NaN when none does.
double crossing(const std::vector<double>& x, const std::vector<double>& err, double limit) {
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (err[i] <= limit || !(err[i - 1] <= limit)) continue;
    const double s = (std::log(limit) - std::log(std::max(err[i - 1], 1e-12))) / (std::log(err[i]) - std::log(std::max(err[i - 1], 1e-12)));
    return std::exp(std::log(x[i - 1]) + s * (std::log(x[i]) - std::log(x[i - 1])));
  }
  return std::nan("");
}

}  // namespace

nlohmann::json study_thin(const StudyContext& ctx) {
  const double limit = 0.1;
  // Thin slab: h = 1, thickness t / h from 4 down to 0.1 (descending: resolved first).
  const std::vector<double> ratios =
      ctx.quick ? std::vector<double>{8, 2, 0.5} : std::vector<double>{16, 12, 8, 6, 4, 3, 2, 1.5, 1, 0.7, 0.5, 0.3, 0.2, 0.1};
  CsvTable slab(ctx.csv_dir / "thin_slab.csv",
                {"case", "thickness_over_h", "half_cells", "elements", "force_ratio", "error", "deflection_error", "thin_elements"});
  std::vector<double> tx, terr;
  double compression_err = 0.0;
  for (double r : ratios) {
    const BentPlateResult b = bent_plate(r, 1.0);
    const double err = std::abs(b.moment_ratio - 1.0);
    slab.row({std::string("bending"), r, 6.0, double(b.elements), b.moment_ratio, err, b.deflection_error, double(b.thin_elements)});
    tx.push_back(r), terr.push_back(err);
    if (r > 4.0 || (ctx.quick && r > 1.0)) continue;  // quick: one compressed slab
    const ThinSlabResult s = thin_slab_press(r, 1.0, 4);
    compression_err = std::max(compression_err, std::abs(s.force_ratio - 1.0));
    slab.row(
        {std::string("compression"), r, 4.0, double(s.elements), s.force_ratio, std::abs(s.force_ratio - 1.0), std::nan(""), std::nan("")});
  }
  // Tool size: contact radius a = 1 over the element size under it, punch and sphere (R = 20).
  const std::vector<double> ah =
      ctx.quick ? std::vector<double>{4, 1.5, 0.6} : std::vector<double>{6, 4, 3, 2, 1.5, 1.2, 1, 0.8, 0.6, 0.5, 0.35, 0.25};
  CsvTable tool(ctx.csv_dir / "tool_size.csv", {"tool", "radius_over_h", "elements", "contact_elements", "force_ratio", "error"});
  std::vector<double> punch_err, sphere_err;
  for (double r : ah) {
    const double h = 1.0 / r, L = ctx.quick ? 20.0 : 100.0;
    const ContactBlock b = contact_block(h, 1.0, L, 1.5 + h);
    const PressResult p = press_block(b, ToolSpec::flat(1.0), 0.01);
    const double fp = 2.0 * contact_e_star() * 0.01, ep = std::abs(p.force / fp - 1.0);
    tool.row({std::string("punch"), r, double(b.mesh->num_elements()), double(p.contact_elements), p.force / fp, ep});
    const PressResult s = press_block(b, ToolSpec::sphere(20.0), 0.05);
    const double fs = 4.0 / 3.0 * contact_e_star() * std::sqrt(20.0) * std::pow(0.05, 1.5), es = std::abs(s.force / fs - 1.0);
    tool.row({std::string("sphere"), r, double(b.mesh->num_elements()), double(s.contact_elements), s.force / fs, es});
    punch_err.push_back(ep), sphere_err.push_back(es);
  }
  nlohmann::json j;
  j["parameter"] =
      "local thickness / element size t / h (a plate bent, a slab compressed), contact radius / element size a / h (flat punch, sphere)";
  j["threshold"] = crossing(tx, terr, limit);  // bending: the 10 % point of the end moment
  j["warning_ratio"] = 1.0;                    // find_thin_elements: size > thickness
  j["punch_threshold"] = crossing(ah, punch_err, limit);
  j["sphere_threshold"] = crossing(ah, sphere_err, limit);
  j["punch_limit"] = kMinPunchRadiusPerElement;
  j["sphere_limit"] = kMinSphereContactRadiusPerElement;
  j["threshold_text"] = "A bent plate's reaction is more than 10 % off below t / h = " + general_text(j["threshold"].get<double>(), 3) +
                        " (too stiff; compressed through its thickness it stays within " + general_text(100.0 * compression_err, 2) +
                        " % down to t / h = " + general_text(ratios.back(), 2) +
                        "); the tool's force is more "
                        "than 10 % off below contact radius / h = " +
                        general_text(j["punch_threshold"].get<double>(), 3) + " for the flat punch and " +
                        general_text(j["sphere_threshold"].get<double>(), 3) + " for the sphere.";
  j["behaviour"] =
      "Loading a scene warns where elements are larger than the body is thick (find_thin_elements, mesh/mesh_thickness.hpp; "
      "the text, thin_elements_warning, also asks for " +
      general_text(kBendingAccurateThicknessPerElement, 3) +
      " elements across a bent part); bemsurg press and the session warn when the contact radius is below " +
      general_text(kMinPunchRadiusPerElement, 3) + " (punch) or " + general_text(kMinSphereContactRadiusPerElement, 3) +
      " (sphere) element sizes (check_tool_resolution, presolution/contact_validity.hpp).";
  j["csv"] = {"thin_slab.csv", "tool_size.csv"};
  return j;
}

nlohmann::json study_depth(const StudyContext& ctx) {
  // A sphere and a flat punch of radius R = 1 on the truncated half-space block (top spacing h
  // within 1.5 R of the axis), pressed from depth / R = 0.01 to 2 through ToolContactSolver with
  // the depth check switched off (ContactDepthLimits::for_studies(): it only measures the strains).
  const double R = 1.0, h = ctx.quick ? 0.25 : 0.125, L = ctx.quick ? 20.0 : 50.0, E_star = contact_e_star();
  const std::vector<double> depths = ctx.quick ? std::vector<double>{0.05, 0.1, 0.3, 0.5, 1.0, 2.0}
                                               : std::vector<double>{0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5, 2.0};
  const ContactBlock b = contact_block(h, R, L, R + h);
  CsvTable csv(ctx.csv_dir / "depth.csv",
               {"tool", "depth_over_radius", "force", "hertz_force", "sneddon_force", "linear_force", "contact_elements",
                "contact_radius_over_radius", "sneddon_contact_radius_over_radius", "checked"});
  const ContactDepthLimits limits;
  // The element under the tools' axis: where press and the session check the tool's resolution.
  Index under = -1;
  for (Index e = 0; e < b.mesh->num_elements(); ++e)
    if (b.mesh->normal(e).z() > 0.9 && (under < 0 || b.mesh->centroid(e).head<2>().norm() < b.mesh->centroid(under).head<2>().norm()))
      under = e;
  for (double dr : depths) {
    const double d = dr * R;
    // Study option: nothing refused, so every depth is pressed; "checked" says what the CLI and the
    // session would do: both checks they run, the depth range and the tool's resolution (a sphere's
    // footprint sqrt(R d) spans too few elements at small depths; its force is then far off).
    const ContactDepthCheck check = check_contact_depth(*b.mesh, Eigen::Vector3d(0, 0, -1), d, R, ContactDepthLimits::for_studies());
    const auto verdict = [&](bool sphere) -> std::string {
      if (check.tool_strain > limits.max_tool_strain) return "refused";
      const bool coarse = !check_tool_resolution(*b.mesh, under, sphere, R, d).warning.empty();
      if (coarse && !check.warning.empty()) return "warned (depth and resolution)";
      if (coarse) return "warned (resolution)";
      return check.warning.empty() ? "ok" : "warned (depth)";
    };
    double a_sneddon = 0.0;
    const double sneddon = sneddon_sphere_force(E_star, R, d, &a_sneddon), hertz = 4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(d, 1.5);
    const PressResult s = press_block(b, ToolSpec::sphere(R), d);
    double reach = 0.0;
    for (Index e : s.elements) reach = std::max(reach, b.mesh->centroid(e).head<2>().norm());
    csv.row({std::string("sphere"), dr, s.force, hertz, sneddon, std::nan(""), double(s.contact_elements), reach / R, a_sneddon / R,
             verdict(true)});
    const PressResult p = press_block(b, ToolSpec::flat(R), d);
    csv.row({std::string("punch"), dr, p.force, std::nan(""), std::nan(""), 2.0 * R * E_star * d, double(p.contact_elements), 1.0,
             std::nan(""), verdict(false)});
  }
  // Where Hertz's small-depth force departs 5 % from the exact sphere's linear-elastic force
  // (bisection on Sneddon's closed form: no mesh in it).
  double lo = 0.01, hi = 2.0;
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (lo + hi), hz = 4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(m * R, 1.5);
    (hz / sneddon_sphere_force(E_star, R, m * R) - 1.0 < 0.05 ? lo : hi) = m;
  }
  double a_at = 0.0;
  sneddon_sphere_force(E_star, R, limits.max_tool_strain * R, &a_at);
  nlohmann::json j;
  j["parameter"] = "press depth / tool radius d / R (sphere and flat punch of radius R)";
  j["threshold"] = lo;
  j["max_tool_strain"] = limits.max_tool_strain;
  j["warn_tool_strain"] = limits.warn_tool_strain;
  j["contact_radius_at_max"] = a_at / R;
  j["threshold_text"] = "Hertz's small-depth force departs 5 % from the linear-elastic force of the exact sphere (Sneddon) at d / R = " +
                        general_text(lo, 3) + "; at max_tool_strain = " + general_text(limits.max_tool_strain, 3) +
                        " the contact radius is already " + general_text(a_at / R, 2) +
                        " R, and it reaches R only as d grows without bound (the linear model never sees the tool's equator).";
  j["behaviour"] =
      "check_contact_depth (presolution/contact_validity.hpp), called by bemsurg press and the session for every press, warns "
      "above depth / radius " +
      general_text(limits.warn_tool_strain, 3) + " and refuses with ContactError above " + general_text(limits.max_tool_strain, 3) +
      " (confirmed); check_tool_resolution, called by both as well, warns when the contact radius (the punch's, or the sphere's "
      "footprint sqrt(R d)) spans fewer than " +
      general_text(kMinPunchRadiusPerElement, 3) + " (punch) or " + general_text(kMinSphereContactRadiusPerElement, 3) +
      " (sphere) element sizes under the tool, which is what makes the shallow sphere presses far off here. ToolContactSolver "
      "itself does not check, and ContactDepthLimits::for_studies() switches the refusal off for studies.";
  j["csv"] = {"depth.csv"};
  return j;
}

}  // namespace bemsurg::bench::stability
