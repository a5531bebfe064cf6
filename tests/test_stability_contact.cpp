// test_stability_contact.cpp: stability studies (g) thin parts and tool size against element size
// and (h) press depth against tool radius (docs/stability.md; the sweeps: bench_stability --study
// thin | depth, benchmarks/stability/contact_studies.cpp). Both sides of each threshold.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "support/half_space_table.hpp"
#include "support/studies/contact_setup.hpp"

using namespace bemsurg;
namespace st = bemsurg::bench::stability;

TEST_CASE("thin part: a bent plate is accurate at 8 elements across, far off and warned below one, and compression is exact",
          "[stability][thin]") {
  // Saint-Venant's pure bending, exact field on the ends (contact_setup.hpp): the reaction moment.
  const st::BentPlateResult thick = st::bent_plate(8.0, 1.0, 3, 1);
  CHECK(std::abs(thick.moment_ratio - 1.0) < 0.1);
  CHECK(thick.thin_elements == 0);
  const st::BentPlateResult thin = st::bent_plate(0.5, 1.0, 3, 1);
  CHECK(thin.moment_ratio > 2.0);  // far off: too stiff
  CHECK(thin.thin_elements > 0);
  // The same thinness under uniform compression (uniaxial strain, closed form) stays exact.
  CHECK(std::abs(st::thin_slab_press(0.5, 1.0, 2).force_ratio - 1.0) < 0.02);
  // The warning's text names the element, its size and thickness and the accurate ratio.
  const TriangleMesh plate = box_mesh_from_grid({-3, -2, -1, 0, 1, 2, 3}, {-1, 0, 1}, {-0.25, 0.25});
  const ThinElements found = find_thin_elements(plate);
  const std::string w = thin_elements_warning(found);
  CHECK(found.count > 0);
  CHECK(w.find("thickness 0.5") != std::string::npos);
  CHECK(w.find("to 7 elements across") != std::string::npos);
  CHECK(thin_elements_warning(ThinElements{}).empty());
}

TEST_CASE("tool size: check_tool_resolution warns below the limit, naming radius, element size and limit", "[stability][thin]") {
  const TriangleMesh grid = box_mesh_from_grid({-2, -1, 0, 1, 2}, {-2, -1, 0, 1, 2}, {-1, 0});  // element size 1
  Index top = 0;
  while (grid.normal(top).z() < 0.99) ++top;
  CHECK(check_tool_resolution(grid, top, false, 1.01 * kMinPunchRadiusPerElement, 0.01).warning.empty());
  const ToolResolutionCheck punch = check_tool_resolution(grid, top, false, 1.4, 0.01);  // just below 1.5
  CHECK(punch.warning.find("punch radius 1.4 is 1.4 element sizes") != std::string::npos);
  CHECK(punch.warning.find("element sizes (1 under") != std::string::npos);
  CHECK(punch.warning.find("below 1.5") != std::string::npos);
  // The sphere's contact radius is Hertz's sqrt(R d): R = 20, d = 0.32 gives 2.53 (inside), 0.3 gives 2.45.
  CHECK(check_tool_resolution(grid, top, true, 20.0, 0.32).warning.empty());
  const ToolResolutionCheck sphere = check_tool_resolution(grid, top, true, 20.0, 0.3);
  CHECK(sphere.warning.find("contact radius 2.45") != std::string::npos);
  CHECK(sphere.warning.find("below 2.5") != std::string::npos);
}

TEST_CASE("tool size: a sphere's force against Hertz on both sides of its resolution limit", "[stability][thin]") {
  // Boussinesq's half-space table (tests/support): the contact discretisation alone.
  const Material m{1.0, 0.3, 0.0};
  const double R = 0.2, E_star = 1.0 / (1.0 - 0.09);
  auto hertz_error = [&](double a_over_h) {
    const double a = 0.004, h = a / a_over_h, d = a * a / R;
    const haptics::HalfSpaceBlock b = haptics::half_space_block(h, 0.01, 1.6 * a, 1.6 * a + h, m);
    const st::ContactBlock block{b.mesh, b.table, b.table->region()};
    const st::PressResult p = st::press_block(block, ToolSpec::sphere(R), d);
    return std::abs(p.force / (4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(d, 1.5)) - 1.0);
  };
  CHECK(hertz_error(1.1 * kMinSphereContactRadiusPerElement) < 0.1);
  CHECK(hertz_error(0.5 * kMinSphereContactRadiusPerElement) > 0.1);
}

TEST_CASE("press depth: refused just past max_tool_strain, accurate just inside, and a sphere past 2 R keeps its force",
          "[stability][depth]") {
  const TriangleMesh body = box_mesh(Eigen::Vector3d(-5, -5, -10), Eigen::Vector3d(5, 5, 0), 1, 1, 1);
  const Eigen::Vector3d down(0, 0, -1);
  const ContactDepthLimits limits;
  CHECK_NOTHROW(check_contact_depth(body, down, 0.99 * limits.max_tool_strain, 1.0));
  try {
    check_contact_depth(body, down, 1.01 * limits.max_tool_strain, 1.0);
    FAIL("a press past max_tool_strain was accepted");
  } catch (const ContactError& e) {
    const std::string what = e.what();
    CHECK(what.find("0.505 times the tool radius 1") != std::string::npos);
    CHECK(what.find("at most 0.5 radius") != std::string::npos);
  }
  // The study option measures without refusing, and keeps the warning.
  const ContactDepthCheck studied = check_contact_depth(body, down, 2.0, 1.0, ContactDepthLimits::for_studies());
  CHECK(studied.tool_strain == Approx(2.0));
  CHECK_FALSE(studied.warning.empty());
  // Just inside the limit the sphere's force follows the exact sphere (Sneddon) on the half-space
  // table; Hertz is already 5 % above it there. Past 2 R the sphere had left every centroid behind
  // and its force dropped to zero (docs/stability.md (h)): now it keeps pushing.
  const Material m{1.0, 0.3, 0.0};
  const double R = 0.005, E_star = 1.0 / (1.0 - 0.09);
  const haptics::HalfSpaceBlock b = haptics::half_space_block(R / 4.0, 0.01, 1.2 * R, 1.2 * R, m);
  const st::ContactBlock block{b.mesh, b.table, b.table->region()};
  const double d = 0.99 * limits.max_tool_strain * R;
  const double sneddon = st::sneddon_sphere_force(E_star, R, d), hertz = 4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(d, 1.5);
  CHECK(hertz / sneddon > 1.04);
  CHECK(std::abs(st::press_block(block, ToolSpec::sphere(R), d).force / sneddon - 1.0) < 0.1);
  const double f15 = st::press_block(block, ToolSpec::sphere(R), 1.5 * R).force,
               f25 = st::press_block(block, ToolSpec::sphere(R), 2.5 * R).force;
  CHECK(std::isfinite(f25));
  CHECK(f25 > f15);
  CHECK(f15 > 0.0);
}
