// `bemsurg cut SCENE.json --from X,Y,Z --direction DX,DY,DZ --steps K [--update METHOD] [--gap W]
// -o OUTDIR`: cut a scene's body step by step (Wang et al. 2007 §5.3; docs/design.md §7;
// docs/cutting.md) and write the cut surface, the solution on it under the scene's loads and a
// report of every step (docs/cli.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend_choice.hpp"
#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/io/scene_table.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"
#include "scene_table.hpp"

namespace {

using bemsurg::cli::UsageError;

constexpr const char* kCutUsage =
    "usage: bemsurg cut SCENE.json --from X,Y,Z --direction DX,DY,DZ --steps K\n"
    "                   [--update exact|gmres|bicgstab|bicg|refactor] [--gap W] -o OUTDIR [--quiet]\n"
    "\n"
    "Opens a narrow cut at the surface vertex nearest X,Y,Z along the mesh edge best aligned with\n"
    "the direction, then extends it by one edge per step (K steps in all). After every step the BEM\n"
    "system and the pre-solution table (region: the scene's operating_region, else every free element)\n"
    "are updated:\n"
    "  exact     bordering by partitioning + low-rank correction of the kept LU (default)\n"
    "  gmres, bicgstab, bicg   iterative re-solve warm-started from the previous solution\n"
    "  refactor  full re-assembly and a new factorisation (the reference)\n"
    "New cut walls are traction-free; elements with a prescribed displacement or a non-zero\n"
    "traction are never cut (the same rules as bemsurg session and the viewer).\n"
    "\n"
    "writes OUTDIR/mesh.obj (the cut surface), OUTDIR/elements.csv (as bemsurg solve, one row per\n"
    "face of mesh.obj), OUTDIR/report.json (\"elements\", \"equations\", \"steps\") and\n"
    "OUTDIR/solved_mesh.obj (the scene's mesh before the cut: the elements warnings name). A refused step\n"
    "is reported with its reason; the command then exits 1 after writing what the completed steps\n"
    "produced.\n";

struct CutCommandOptions {
  std::string scene, output;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::Zero();
  int steps = 0;
  bemsurg::CutUpdateMethod update = bemsurg::CutUpdateMethod::Exact;
  double gap = 0.0;  // 0: the cutter's default, 0.1 x the local edge length
  bool quiet = false;
};

/// The options, or nothing after --help (printed).
std::optional<CutCommandOptions> parse_cut_options(int argc, char** argv) {
  CutCommandOptions o;
  bemsurg::cli::OptionParser parser("cut", kCutUsage);
  parser.positional("SCENE.json", o.scene, "one scene file per run").required();
  bemsurg::cli::vector3_value(parser, "--from", "X,Y,Z", o.from, "where the cut starts (the nearest surface vertex)").required();
  bemsurg::cli::vector3_value(parser, "--direction", "DX,DY,DZ", o.direction, "the direction it runs along").required();
  parser.value("--steps", "K", o.steps, "cut steps, one mesh edge each").required().at_least(1);
  parser
      .custom_value("--update", "METHOD", "exact, gmres, bicgstab, bicg or refactor (see above)",
                    [&o](const std::string& text) {
                      try {
                        o.update = bemsurg::parse_cut_update_method(text);
                      } catch (const bemsurg::Error&) { throw std::invalid_argument("exact, gmres, bicgstab, bicg or refactor"); }
                    })
      .default_text("exact");
  parser.value("--gap", "W", o.gap, "gap width").above(0.0).default_text("0.1 x the local edge length");
  parser.value("-o, --output", "OUTDIR", o.output, "output directory").required();
  parser.flag("-q, --quiet", o.quiet, "print nothing but warnings and errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return std::nullopt;
  }
  if (!(o.direction.norm() > 0.0)) throw UsageError("cut: --direction must not be zero");
  return o;
}

void write_json(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  if (!out) throw bemsurg::IoError("cannot write " + path);
  out << std::setw(2) << j << "\n";
  if (!out) throw bemsurg::IoError("writing " + path + " failed");
}

/// The scene again with its mesh replaced by `obj`: what `bemsurg solve` of such a scene would
/// prescribe. Returns the first element whose conditions differ from `bc` (-1: none).
bemsurg::Index first_condition_mismatch(const std::string& scene_path, const std::string& obj, const bemsurg::BoundaryConditions& bc) {
  const bemsurg::Scene again = bemsurg::load_scene_with_mesh(scene_path, obj);
  const bemsurg::BoundaryConditions& other = again.problem.boundary_conditions;
  if (other.num_dofs() != bc.num_dofs()) return 0;
  for (bemsurg::Index k = 0; k < bc.num_dofs(); ++k)
    if (other.kind(k) != bc.kind(k) || other.value(k) != bc.value(k)) return k / 3;
  return -1;
}

/// report.json's entry for a step that was refused (docs/cli.md, `bemsurg cut`).
nlohmann::json refused_step_json(const std::string& reason, bemsurg::Index equations, bemsurg::CutUpdateMethod update, double seconds) {
  return {{"accepted", false},
          {"reason", reason},
          {"added", 0},
          {"modified", 0},
          {"removed", 0},
          {"equations", equations},
          {"update", to_string(update)},
          {"iterations", 0},
          {"seconds", seconds},
          {"integration_seconds", 0.0}};
}

/// report.json's entry for an accepted step.
nlohmann::json accepted_step_json(const bemsurg::MeshDelta& delta, const bemsurg::CutStepResult& r, bemsurg::CutUpdateMethod update,
                                  double seconds) {
  return {{"accepted", true},
          {"added", delta.added.size()},
          {"modified", delta.modified.size()},
          {"removed", delta.removed.size()},
          {"equations", 3 * delta.elements_after},
          {"update", to_string(update)},
          {"iterations", r.iterations},
          {"seconds", seconds},
          {"integration_seconds", r.integration_seconds},
          {"rank", r.rank},
          {"refactor_started", r.refactor_started}};
}

}  // namespace

int run_cut(int argc, char** argv) {
  using namespace bemsurg;
  const std::optional<CutCommandOptions> parsed = parse_cut_options(argc, argv);
  if (!parsed) return 0;
  const CutCommandOptions& o = *parsed;
  const auto t_start = SteadyClock::now();
  const Scene scene = cli::with_chosen_backend(require_constant_elements(load_scene(o.scene), "bemsurg cut"), o.quiet, "bemsurg cut");
  for (const std::string& w : scene.warnings) std::cerr << "bemsurg: warning: " << o.scene << ": " << w << "\n";
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.output, ec);
  if (ec || !fs::is_directory(o.output))
    throw IoError("cannot create the output directory '" + o.output +
                  "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  const fs::path out(o.output);
  write_obj((out / "solved_mesh.obj").string(), scene.problem.mesh);  // before any cut: what the warnings name

  const ElastostaticProblem& p = scene.problem;
  const Index E = p.mesh.num_elements();
  if (!o.quiet)
    std::cout << "bemsurg cut: " << E << " elements, " << 3 * E << " equations; update " << to_string(o.update) << ", table region "
              << (scene.operating_elements.empty() ? std::string("every free element")
                                                   : std::to_string(scene.operating_elements.size()) + " elements")
              << std::endl;
  // The table of the scene on its operating region and its backend, as press, session and the viewer compute
  // it; computed (never read from a file) because a cut update needs its factorisation (the dense LU or the
  // H-LU: docs/cutting.md, "On either backend").
  auto table = std::make_shared<const GreensTable>(cli::scene_table(scene, "", true, true).table);
  CutSystemOptions sopt;
  sopt.krylov = scene.solver;
  sopt.krylov.tolerance = std::min(scene.solver.tolerance, 1e-12);
  sopt.krylov.restart = 0;
  sopt.krylov.max_iterations = std::max(scene.solver.max_iterations, 2000);
  CutSystemUpdate system(table, sopt);
  CutOptions copt;
  copt.gap_width = o.gap;
  system.begin_cut(copt);

  nlohmann::json steps = nlohmann::json::array();
  std::string refused;
  for (int i = 0; i < o.steps; ++i) {
    const auto t0 = SteadyClock::now();
    const CutStepResult r = system.cut(o.from, o.direction, o.update);
    if (!r.accepted) {
      refused = "step " + std::to_string(i + 1) + " refused: " + r.reason;
      steps.push_back(refused_step_json(r.reason, system.table()->num_dofs(), o.update, seconds_since(t0)));
      break;
    }
    const double seconds = seconds_since(t0);
    steps.push_back(accepted_step_json(r.delta, r, o.update, seconds));
    if (!o.quiet)
      std::cout << "  step " << i + 1 << ": +" << r.delta.added.size() << " elements, " << r.delta.modified.size() << " modified, "
                << 3 * r.delta.elements_after << " equations, " << std::setprecision(3) << seconds << " s (integration "
                << r.integration_seconds << " s" << (r.iterations > 0 ? ", " + std::to_string(r.iterations) + " iterations" : "") << ")"
                << std::endl;
  }
  system.wait_for_refactor();
  const std::shared_ptr<const GreensTable> final_table = system.table();
  const TriangleMesh& cut_mesh = *final_table->mesh();
  const std::string obj = (out / "mesh.obj").string();
  write_obj(obj, cut_mesh);
  write_elements_csv((out / "elements.csv").string(), cut_mesh, system.boundary_solution());
  nlohmann::json report = {
      {"scene", o.scene},
      {"elements", cut_mesh.num_elements()},
      {"equations", cut_mesh.num_dofs()},
      {"update", to_string(o.update)},
      {"table_backend", to_string(table->key().backend)},
      {"table_region_elements", final_table->region().size()},
      {"precompute_seconds", table->timings().assembly_seconds + table->timings().factorization_seconds + table->timings().table_seconds},
      {"steps", steps},
      {"total_seconds", seconds_since(t_start)}};
  if (!refused.empty()) report["refused"] = refused;
  write_json((out / "report.json").string(), report);
  const Index mismatch = first_condition_mismatch(o.scene, obj, final_table->base_conditions());
  if (mismatch >= 0)
    std::cerr << "bemsurg: warning: the scene's rules applied to mesh.obj prescribe other conditions on element " << mismatch
              << " than the cut carried over; `bemsurg solve` of that scene will not reproduce elements.csv\n";
  if (!refused.empty()) {
    std::cerr << "bemsurg: error: cut: " << refused << " (wrote the " << steps.size() - 1 << " completed step(s) to " << o.output << ")\n";
    return 1;
  }
  if (!o.quiet) std::cout << "  wrote " << obj << ", " << (out / "elements.csv").string() << ", " << (out / "report.json").string() << "\n";
  return 0;
}
