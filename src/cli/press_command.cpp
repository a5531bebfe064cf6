// `bemsurg press SCENE.json --tool point|flat:RADIUS|sphere:RADIUS --at X,Y,Z --direction DX,DY,DZ
// --depth D [--frictionless] -o OUTDIR`: one tool pressed into a scene through the pre-solution
// table and exact capacitance contact (docs/design.md §6; Wang et al. 2007 §5.1-5.2). The tool comes
// down along the direction onto the self-weight surface near X,Y,Z and pushes D beyond first
// contact. Writes OUTDIR/elements.csv (as `bemsurg solve`), OUTDIR/solved_mesh.obj and OUTDIR/force.json.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "backend_choice.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"
#include "scene_table.hpp"

namespace {

using bemsurg::SteadyClock;
using bemsurg::cli::UsageError;

constexpr const char* kPressUsage =
    "usage: bemsurg press SCENE.json --tool point|flat:RADIUS|sphere:RADIUS --at X,Y,Z\n"
    "                     --direction DX,DY,DZ --depth D [--frictionless] -o OUTDIR\n"
    "                     [--table FILE] [--quiet]\n"
    "\n"
    "The tool comes down along DIRECTION on the line through X,Y,Z onto the body (deformed by its\n"
    "own weight), stops at first contact and pushes DEPTH further. Contact is exact (capacitance\n"
    "matrix on the pre-solution table): bonded unless --frictionless (normal component only).\n"
    "flat: rigid flat disc of radius RADIUS; sphere: rigid sphere of radius RADIUS (unilateral:\n"
    "elements that would pull are released). The point tool's force depends on the mesh size.\n"
    "\n"
    "DEPTH must stay in the small-strain range (docs/design.md §6): refused beyond 20 % of the body's\n"
    "extent along DIRECTION or 0.5 x RADIUS (flat, sphere); a warning above 5 % or 0.1 x RADIUS.\n"
    "\n"
    "writes OUTDIR/elements.csv (as bemsurg solve), OUTDIR/solved_mesh.obj (the mesh pressed: the\n"
    "elements warnings name) and OUTDIR/force.json:\n"
    "  {\"force\": [fx, fy, fz], \"contact_elements\": k, \"force_update_us\": time of one force evaluation, ...}\n";

struct PressOptions {
  std::string scene, output, table_file, tool_text;
  bemsurg::ToolSpec tool;
  Eigen::Vector3d at = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::Zero();
  double depth = 0.0, tool_radius = 0.0;  // tool_radius: 0 for the point tool
  bool frictionless = false, quiet = false;
};

/// The options, or nothing after --help (printed).
std::optional<PressOptions> parse(int argc, char** argv) {
  PressOptions o;
  bemsurg::cli::OptionParser parser("press", kPressUsage);
  parser.positional("SCENE.json", o.scene, "one scene file only").required();
  parser.value("--tool", "point|flat:RADIUS|sphere:RADIUS", o.tool_text, "the tool's shape").required();
  bemsurg::cli::vector3_value(parser, "--at", "X,Y,Z", o.at, "a point on the line the tool comes down along").required();
  bemsurg::cli::vector3_value(parser, "--direction", "DX,DY,DZ", o.direction, "the direction it comes down along (any length)").required();
  parser.value("--depth", "D", o.depth, "how far it pushes beyond first contact").required().at_least(0.0);
  parser.flag("--frictionless", o.frictionless, "normal contact only (default: bonded)");
  parser.value("-o, --output", "OUTDIR", o.output, "output directory").required();
  parser.value("--table", "FILE", o.table_file,
               "load the pre-solution table from FILE when it matches the scene, else compute\n"
               "it and save it there (a stale or corrupt file is reported and recomputed)");
  parser.flag("-q, --quiet", o.quiet, "print nothing but errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return std::nullopt;
  }
  // stableNorm: 1e-200,0,0 and 1e200,0,0 are directions too (norm() under- or overflows there).
  const double direction_norm = o.direction.stableNorm();
  if (!(direction_norm > 0.0) || !std::isfinite(direction_norm)) throw UsageError("press: --direction must be a finite, nonzero vector");
  o.direction /= direction_norm;
  const auto mode = o.frictionless ? bemsurg::ContactMode::Frictionless : bemsurg::ContactMode::Bonded;
  const std::string& t = o.tool_text;
  auto radius = [&](const std::string& prefix) {
    const std::optional<double> r = bemsurg::parse_number<double>(std::string_view(t).substr(prefix.size()));
    if (!r || !std::isfinite(*r))
      throw UsageError("press: --tool " + prefix + "RADIUS: expected a finite number, got '" + t.substr(prefix.size()) + "'");
    if (!(*r > 0.0)) throw UsageError("press: the " + prefix.substr(0, prefix.size() - 1) + " radius must be positive");
    return *r;
  };
  if (t == "point")
    o.tool = bemsurg::ToolSpec::point(mode);
  else if (t.rfind("flat:", 0) == 0)
    o.tool = bemsurg::ToolSpec::flat(o.tool_radius = radius("flat:"), mode);
  else if (t.rfind("sphere:", 0) == 0)
    o.tool = bemsurg::ToolSpec::sphere(o.tool_radius = radius("sphere:"), mode);
  else
    throw UsageError("press: --tool must be point, flat:RADIUS or sphere:RADIUS, got '" + t + "'");
  return o;
}

/// One force evaluation at the current contact set (targets in, force out through the 3 x k
/// force operator), in microseconds: the median of many, reported as force_update_us.
double median_force_update_us(bemsurg::CapacitanceContact& contact) {
  std::vector<double> targets(static_cast<std::size_t>(contact.num_rows()));
  for (bemsurg::Index a = 0; a < contact.num_rows(); ++a) targets[static_cast<std::size_t>(a)] = contact.target(a);
  std::vector<double> us;
  const int reps = 2001;
  us.reserve(reps);
  volatile double sink = 0.0;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = SteadyClock::now();
    for (bemsurg::Index a = 0; a < contact.num_rows(); ++a) contact.set_target(a, targets[static_cast<std::size_t>(a)]);
    sink = sink + contact.force_for_targets()(2);
    us.push_back(std::chrono::duration<double, std::micro>(SteadyClock::now() - t0).count());
  }
  (void)sink;
  std::nth_element(us.begin(), us.begin() + reps / 2, us.end());
  return us[reps / 2];
}

}  // namespace

int run_press(int argc, char** argv) {
  const std::optional<PressOptions> parsed = parse(argc, argv);
  if (!parsed) return 0;
  const PressOptions& o = *parsed;
  const auto t_start = SteadyClock::now();
  const bemsurg::Scene scene = bemsurg::cli::with_chosen_backend(
      bemsurg::require_constant_elements(bemsurg::load_scene(o.scene), "bemsurg press"), o.quiet, "bemsurg press");
  if (!o.quiet)
    for (const auto& w : scene.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
  const bemsurg::ElastostaticProblem& p = scene.problem;
  // The mesh pressed, before the table: the element numbers of every warning refer to it.
  std::filesystem::create_directories(o.output);
  bemsurg::write_obj((std::filesystem::path(o.output) / "solved_mesh.obj").string(), p.mesh);
  // The depth must lie in the model's small-strain range (docs/design.md §6): refused before the
  // table is computed, with a warning between the warning and the refusal thresholds.
  const bemsurg::ContactDepthCheck range = bemsurg::check_contact_depth(p.mesh, o.direction, o.depth, o.tool_radius);
  if (!o.quiet && !range.warning.empty()) std::cerr << "bemsurg: warning: press: " << range.warning << "\n";

  // The table: loaded when a matching file matches, else computed (and saved): scene_table.hpp.
  bemsurg::CachedGreensTable cached = bemsurg::cli::scene_table(scene, o.table_file, o.quiet);
  bemsurg::GreensTable& table = cached.table;
  const bool loaded = cached.loaded_from_file;

  // The solver holds shared immutable snapshots of the mesh and the table (docs/design.md §9).
  const auto mesh_ptr = std::make_shared<const bemsurg::TriangleMesh>(p.mesh);
  const auto table_ptr = std::make_shared<const bemsurg::GreensTable>(std::move(table));
  const bemsurg::GreensTable& table_ref = *table_ptr;
  bemsurg::ToolContactSolver solver(mesh_ptr, table_ptr, std::max<bemsurg::Index>(300, 3 * p.mesh.num_elements() / 4));
  const int tool = solver.add_tool(o.tool);
  if (!solver.engage(tool, o.at, o.direction))
    throw bemsurg::ContactError("press: a tool coming along (" + bemsurg::fixed_text(o.direction.x(), 6) + ", " +
                                bemsurg::fixed_text(o.direction.y(), 6) + ", " + bemsurg::fixed_text(o.direction.z(), 6) +
                                ") through the given point does not meet the body (or only outside the table's region, or the "
                                "sphere is narrower than the elements where it lands and covers no element centroid)");
  // A tool narrower than a few elements gives a coarse force (docs/stability.md (g)): warned, with
  // the element size under the tool's axis (the ray from one radius behind the engaged origin).
  if (o.tool_radius > 0.0 && !o.quiet) {
    bemsurg::RayHit hit;
    const Eigen::Vector3d dir = solver.direction(tool);
    if (solver.base_surface().intersect_ray(solver.origin(tool) - o.tool_radius * dir, dir, hit)) {
      const bemsurg::ToolResolutionCheck res =
          bemsurg::check_tool_resolution(p.mesh, hit.element, o.tool.shape == bemsurg::ToolShape::Sphere, o.tool_radius, o.depth);
      if (!res.warning.empty()) std::cerr << "bemsurg: warning: press: " << res.warning << "\n";
    }
  }
  solver.set_depth(tool, o.depth);
  const bemsurg::ContactUpdateResult report = solver.update();
  const Eigen::Vector3d force = solver.force(tool);
  // Never a NaN or a sudden zero (docs/design.md §10): inside the depth range the contact set is
  // never empty once the tool pushes, so an empty one or a non-finite force is a failure to report.
  if (!force.allFinite())
    throw bemsurg::ContactError("press: the contact force is not finite at depth " + bemsurg::fixed_text(o.depth, 6) +
                                " (the contact solve failed); try a smaller --depth");
  if (o.depth > 0.0 && solver.contact_elements(tool) == 0)
    throw bemsurg::ContactError("press: the tool pushed " + bemsurg::fixed_text(o.depth, 6) +
                                " beyond first contact but no element is in contact (the contact set emptied); "
                                "try a smaller --depth or a wider tool");

  auto& contact = solver.contact();
  const double force_update_us = median_force_update_us(contact);

  // Full field and the per-element output, as `bemsurg solve` writes it.
  const bemsurg::Index E = p.mesh.num_elements();
  Eigen::VectorXd u(3 * E);
  solver.displacement_field(u);
  bemsurg::BoundarySolution out{bemsurg::RowMatrixX3d(E, 3), bemsurg::RowMatrixX3d(E, 3)};
  for (bemsurg::Index e = 0; e < E; ++e) {
    out.displacement.row(e) = u.segment<3>(3 * e).transpose();
    out.traction.row(e) = (contact.contains(e) ? contact.traction(e) : table_ref.base_traction().segment<3>(3 * e)).transpose();
  }
  std::filesystem::create_directories(o.output);
  bemsurg::write_elements_csv((std::filesystem::path(o.output) / "elements.csv").string(), p.mesh, out);

  nlohmann::json j;
  j["force"] = {force.x(), force.y(), force.z()};
  j["contact_elements"] = solver.contact_elements(tool);
  j["force_update_us"] = force_update_us;
  j["tool"] = o.tool_text;
  j["frictionless"] = o.frictionless;
  j["depth"] = o.depth;
  j["active_set_iterations"] = report.active_set_iterations;
  j["active_set_consistent"] = report.consistent;
  j["equations"] = 3 * E;
  j["table"] = {{"loaded_from_file", loaded},
                {"backend", bemsurg::to_string(table_ref.key().backend)},
                {"compression_tolerance", table_ref.key().compression_tolerance},
                {"assembly_seconds", table_ref.timings().assembly_seconds},
                {"factorization_seconds", table_ref.timings().factorization_seconds},
                {"table_seconds", table_ref.timings().table_seconds}};
  j["total_seconds"] = bemsurg::seconds_since(t_start);
  const std::string json_path = (std::filesystem::path(o.output) / "force.json").string();
  std::ofstream js(json_path);
  if (!js) throw bemsurg::IoError("cannot write " + json_path);
  js << std::setw(2) << j << "\n";
  if (!js) throw bemsurg::IoError("writing " + json_path + " failed");
  if (!o.quiet)
    std::cout << "press: " << o.tool_text << " depth " << o.depth << ": force (" << force.x() << ", " << force.y() << ", " << force.z()
              << ") N on " << solver.contact_elements(tool) << " elements; one force update " << force_update_us << " us\n";
  return 0;
}
