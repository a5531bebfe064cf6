// `bemsurg session SCENE.json --script ACTIONS.json -o OUTDIR`: a scripted surgical session
// (docs/actions.md, docs/haptics.md): the script drives scripted haptic devices, the haptic loop
// renders the tools' forces from the pre-solution table at the script's rate, and the command
// writes OUTDIR/force_trace.csv (one row per tool per tick), OUTDIR/report.json (the loop's
// statistics), OUTDIR/solved_mesh.obj (the scene's mesh) and OUTDIR/mesh_after_cut_N.obj after each cut.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "backend_choice.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/haptics/surface_cut_hook.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "commands.hpp"
#include "scene_table.hpp"

namespace {

constexpr const char* kSessionUsage =
    "usage: bemsurg session SCENE.json --script ACTIONS.json -o OUTDIR [--table FILE] [--virtual-clock]\n"
    "                       [--realtime-priority N] [--quiet]\n"
    "\n"
    "Runs the action script (docs/actions.md) on the scene: scripted devices drive the tools, the\n"
    "haptic loop computes their forces from the pre-solution table at the script's rate_hz.\n"
    "\n"
    "writes OUTDIR/force_trace.csv   time,tool,fx,fy,fz,force,contact_elements,x,y,z,model_fx,model_fy,model_fz,status,watchdog_gain,model_version\n"
    "                                 (one row per tool per haptic tick; force = what the device was sent, N)\n"
    "       OUTDIR/report.json       rate_hz, overruns, jitter_us {p50,p99,p999}, force_us {p50,p99,p999},\n"
    "                                 max_force_jump_fraction, min_delivered_force_ratio,\n"
    "                                 max_tick_change_fraction, ... (docs/haptics.md)\n"
    "       OUTDIR/mesh_after_cut_N.obj   the surface after each cut\n"
    "       OUTDIR/solved_mesh.obj   the scene's mesh before any cut (the elements warnings name)\n";

class TraceWriter : public bemsurg::haptics::SessionObserver {
 public:
  TraceWriter(const std::string& dir, const bemsurg::ActionScript& script) : dir_(dir), script_(script) {
    const std::string path = (std::filesystem::path(dir) / "force_trace.csv").string();
    out_.open(path);
    if (!out_) throw bemsurg::IoError("cannot write " + path);
    out_ << "time,tool,fx,fy,fz,force,contact_elements,x,y,z,model_fx,model_fy,model_fz,status,watchdog_gain,model_version\n";
    // The trace is read by other programs: numbers with a point whatever the global locale.
    bemsurg::use_classic_locale(out_) << std::setprecision(9);
  }
  void on_sample(const bemsurg::haptics::TickSample& s) override {
    for (const auto& tool : script_.tools) {
      const auto& c = s.channel[static_cast<std::size_t>(tool.device)];
      out_ << s.time << ',' << tool.name << ',' << c.force.x() << ',' << c.force.y() << ',' << c.force.z() << ',' << c.force.norm() << ','
           << c.contact_elements << ',' << c.position.x() << ',' << c.position.y() << ',' << c.position.z() << ',' << c.model_force.x()
           << ',' << c.model_force.y() << ',' << c.model_force.z() << ',' << bemsurg::to_string(c.status) << ',' << s.watchdog_gain << ','
           << s.model_version << '\n';
    }
  }
  void on_cut(int index, const bemsurg::TriangleMesh& mesh) override {
    const std::string path = (std::filesystem::path(dir_) / ("mesh_after_cut_" + std::to_string(index) + ".obj")).string();
    bemsurg::write_obj(path, mesh);
    meshes_.push_back(path);
  }
  void finish() {
    out_.flush();
    if (!out_) throw bemsurg::IoError("writing " + dir_ + "/force_trace.csv failed");
  }
  const std::vector<std::string>& meshes() const { return meshes_; }

 private:
  std::string dir_;
  const bemsurg::ActionScript& script_;
  std::ofstream out_;
  std::vector<std::string> meshes_;
};

nlohmann::json percentiles_json(const bemsurg::haptics::Percentiles& p) {
  return {{"p50", p.p50}, {"p99", p.p99}, {"p999", p.p999}, {"max", p.max}};
}

/// report.json (docs/cli.md "bemsurg session"): the loop's statistics, what a hand felt, the cuts.
nlohmann::json report_json(const bemsurg::haptics::SessionResult& r, const bemsurg::ActionScript& script,
                           const std::vector<std::string>& meshes, bool virtual_clock, bemsurg::Index elements, bool loaded,
                           bemsurg::SolverBackend table_backend) {
  const auto& s = r.loop;
  nlohmann::json j;
  j["rate_hz"] = s.achieved_rate_hz;
  j["requested_rate_hz"] = s.rate_hz;
  j["overruns"] = s.overruns;
  j["jitter_us"] = percentiles_json(s.jitter_us);
  j["force_us"] = percentiles_json(s.force_us);
  j["max_force_jump_fraction"] = r.max_force_jump_fraction;
  j["min_delivered_force_ratio"] = r.felt.min_delivered_ratio;
  j["min_delivered_force_ratio_time"] = r.felt.min_delivered_ratio_time;
  j["max_tick_change_fraction"] = r.felt.max_tick_change_fraction;
  j["max_tick_change_time"] = r.felt.max_tick_change_time;
  j["cut_step_seconds"] = r.cut_step_seconds;
  j["cut_complete_seconds"] = r.cut_complete_seconds;
  j["cut_steps_waited"] = r.cut_steps_waited;
  j["ticks"] = s.ticks;
  j["dropped_packets"] = s.dropped_packets;
  j["model_swaps"] = s.model_swaps;
  j["models_built"] = r.models_built;
  j["nan_guards"] = s.nan_guards;
  j["failed_steps"] = s.failed_steps;
  j["watchdog_ticks"] = s.watchdog_ticks;
  j["clamped_ticks"] = s.clamped_ticks;
  j["faults"] = s.faults;
  j["trace_dropped"] = s.trace_dropped;
  j["realtime_priority"] = s.realtime_priority;
  j["field_updates"] = r.field_updates;
  j["field_ms"] = percentiles_json(r.field_ms);
  j["cuts"] = r.cuts;
  j["meshes_after_cuts"] = meshes;
  j["clock"] = virtual_clock ? "virtual" : "realtime";
  j["session_seconds"] = script.duration;
  j["wall_seconds"] = r.session_seconds;
  j["elements"] = elements;
  j["table_loaded_from_file"] = loaded;
  j["table_backend"] = bemsurg::to_string(table_backend);
  nlohmann::json tools = nlohmann::json::array();
  for (std::size_t t = 0; t < script.tools.size(); ++t)
    tools.push_back({{"name", script.tools[t].name},
                     {"shape", bemsurg::to_string(script.tools[t].shape)},
                     {"device", script.tools[t].device},
                     {"peak_model_force", r.peak_force[t]}});
  j["tools"] = tools;
  return j;
}

}  // namespace

int run_session(int argc, char** argv) {
  std::string scene_path, script_path, output, table_file;
  bool quiet = false, virtual_clock = false;
  int realtime_priority = bemsurg::haptics::HapticLoopOptions{}.realtime_priority;
  bemsurg::cli::OptionParser parser("session", kSessionUsage);
  parser.positional("SCENE.json", scene_path, "one scene file only").required();
  parser.value("--script", "ACTIONS.json", script_path, "the action script (docs/actions.md)").required();
  parser.value("-o, --output", "OUTDIR", output, "output directory").required();
  parser.value("--table", "FILE", table_file,
               "load the pre-solution table from FILE when it matches the scene, else compute\n"
               "it and save it there");
  parser.flag("--virtual-clock", virtual_clock,
              "run the ticks back to back in session time (deterministic, as fast as the\n"
              "machine goes) instead of in real time on the haptic thread");
  parser
      .value("--realtime-priority", "N", realtime_priority,
             "SCHED_FIFO priority N for the haptic thread (0: do not ask); without the\n"
             "privilege the loop runs at normal priority, says so, and report.json says\n"
             "what it got")
      .between(0, 99);
  parser.flag("-q, --quiet", quiet, "print nothing but errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return 0;
  }

  const bemsurg::ActionScript script = bemsurg::load_action_script(script_path);
  const bemsurg::Scene scene = bemsurg::cli::with_chosen_backend(
      bemsurg::require_constant_elements(bemsurg::load_scene(scene_path), "bemsurg session"), quiet, "bemsurg session");
  if (!quiet) {
    for (const auto& w : scene.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
    for (const auto& w : script.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
  }
  bemsurg::haptics::SessionOptions options;
  options.virtual_clock = virtual_clock;
  options.loop.realtime_priority = realtime_priority;
  const bemsurg::haptics::SurfaceCuts cuts = bemsurg::haptics::surface_cuts();
  options.cut_hook = cuts.hook;
  options.cut_prepare = cuts.prepare;

  const bemsurg::ElastostaticProblem& p = scene.problem;
  // The mesh of the session before any cut: the element numbers of every warning refer to it.
  std::filesystem::create_directories(output);
  bemsurg::write_obj((std::filesystem::path(output) / "solved_mesh.obj").string(), p.mesh);
  // The table: loaded when a matching file is given, else computed on the operating region
  // (and saved when asked): src/cli/scene_table.hpp.
  bemsurg::CachedGreensTable cached = bemsurg::cli::scene_table(scene, table_file, quiet, script.has_cuts(), false, script.has_cuts());
  bemsurg::GreensTable& table = cached.table;
  const bool loaded = cached.loaded_from_file;
  auto mesh_ptr = std::make_shared<const bemsurg::TriangleMesh>(p.mesh);
  auto table_ptr = std::make_shared<const bemsurg::GreensTable>(std::move(table));

  bemsurg::haptics::Session session(mesh_ptr, table_ptr, script, options);
  if (!quiet)
    for (const auto& w : session.warnings()) std::cerr << "bemsurg: warning: session: " << w << "\n";
  std::filesystem::create_directories(output);
  TraceWriter trace(output, session.script());
  const bemsurg::haptics::SessionResult r = session.run(&trace);
  trace.finish();

  const auto& s = r.loop;
  const nlohmann::json j = report_json(r, script, trace.meshes(), virtual_clock, p.mesh.num_elements(), loaded, table_ptr->key().backend);
  const std::string json_path = (std::filesystem::path(output) / "report.json").string();
  std::ofstream js(json_path);
  if (!js) throw bemsurg::IoError("cannot write " + json_path);
  js << std::setw(2) << j << "\n";
  if (!js) throw bemsurg::IoError("writing " + json_path + " failed");
  if (!quiet && !virtual_clock && realtime_priority > 0 && s.realtime_priority == 0)
    std::cerr << "bemsurg: warning: session: SCHED_FIFO priority " << realtime_priority
              << " was refused (needs CAP_SYS_NICE or an rtprio limit): the haptic thread ran at normal priority, where other "
                 "load on this machine can delay its ticks (docs/haptics.md, \"Threads while a loop runs\")\n";
  if (!quiet)
    std::cout << "session: " << s.ticks << " ticks at " << s.achieved_rate_hz << " Hz (" << (virtual_clock ? "virtual" : "real")
              << " clock), " << s.overruns << " overruns, jitter p99.9 " << s.jitter_us.p999 << " us, force p99.9 " << s.force_us.p999
              << " us, largest force jump " << 100.0 * r.max_force_jump_fraction << " %; delivered force at least "
              << 100.0 * r.felt.min_delivered_ratio << " % of the model's, largest tick-to-tick change "
              << 100.0 * r.felt.max_tick_change_fraction << " %; " << r.cuts << " cut steps; wrote " << output << "\n";
  return 0;
}
