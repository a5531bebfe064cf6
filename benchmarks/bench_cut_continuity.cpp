// bench_cut_continuity: feel through a cut (issue 26; docs/haptics.md, "Feeling through a cut").
// A sphere probe is held 3 mm deep on the liver-like organ (examples/scenes/liver.json: graded to
// about 1,800 elements, 5,400 equations) while a 4-step cut runs 10 mm beside it
// (examples/liver-cut-session.json), in real time through Session and the cutting module's exact
// table updates (haptics/surface_cut_hook.hpp), in two configurations run in the same process:
//   * before: the cut step on the simulation thread (no heartbeat while it computes), the new model
//     switched in at once, background work on every core, normal priority (bemsurg 0.3);
//   * after:  the defaults: the step on a background thread (the heartbeat keeps beating), the old
//     model blended into the new over HapticLoopOptions::blend_s, background work on cores - 1
//     threads, SCHED_FIFO asked for (where the machine grants it);
// each quiet and (full run) beside a load of one busy thread per core at normal priority, what a
// compile on the trainee's laptop does; the full run repeats each configuration 5 times, interleaved
// (a VM's stalls come and go), and summarises medians of rate and overruns and the worst felt figures. The baseline, also in the same process: the empty loop (the
// same machinery and script length, the probe in the air, no cut) quiet and loaded.
// Reported per run: achieved rate, overruns per second, the smallest delivered / model force ratio
// and the largest tick-to-tick change of the delivered force (haptics/felt_force.hpp), the model
// force's largest jump, watchdog ticks and each cut step's time; --csv-dir writes the probe's force
// trace of every run (trace_<configuration>_<load>.csv: time, model, delivered, watchdog_gain,
// blend_weight, model_version) for the report's before/after chart. A full run also profiles the
// script's cut steps without the loop ("step_profile": where cut_step_seconds and
// cut_complete_seconds go, issue 39).
//
// usage: bench_cut_continuity [--quick] [--json PATH] [--csv-dir DIR] [--repeat N] [--scene FILE] [--script FILE]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/haptics/background_threads.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/haptics/surface_cut_hook.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/timing.hpp"
#include "bench_support.hpp"

using namespace bemsurg;

namespace {

/// One busy thread per core at normal priority for as long as it lives (the "compile beside it").
class BusyLoad {
 public:
  explicit BusyLoad(bool on) {
    if (!on) return;
    for (unsigned k = 0; k < std::max(1U, std::thread::hardware_concurrency()); ++k)
      threads_.emplace_back([this] {
        volatile double x = 1.0;
        while (!stop_.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
      });
  }
  ~BusyLoad() {
    stop_.store(true);
    for (auto& t : threads_) t.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

/// The probe's force, tick by tick (tool 0).
struct ProbeTrace : haptics::SessionObserver {
  struct Row {
    double time, model, delivered, gain, blend;
    std::uint64_t version;
  };
  std::vector<Row> rows;
  void on_sample(const haptics::TickSample& s) override {
    const auto& c = s.channel[0];
    rows.push_back({s.time, c.model_force.norm(), c.force.norm(), s.watchdog_gain, s.blend_weight, s.model_version});
  }
  bool write(const std::string& path) const {
    std::ofstream out(path);
    use_classic_locale(out);
    out << "time,model,delivered,watchdog_gain,blend_weight,model_version\n";
    for (const Row& r : rows)
      out << general_text(r.time, 9) << ',' << general_text(r.model, 9) << ',' << general_text(r.delivered, 9) << ','
          << general_text(r.gain, 6) << ',' << general_text(r.blend, 6) << ',' << r.version << '\n';
    return static_cast<bool>(out);
  }
};

/// The same probe in the air for the script's length: nothing to compute, no cut.
std::string air_script(double seconds) {
  return R"({"format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
    "tools": [{"name": "probe", "shape": "sphere", "radius": 0.015, "start": [0.022, 0.0, 0.2]}],
    "actions": [{"time": 0.0, "tool": "probe", "type": "move", "to": [0.022, 0.001, 0.2], "duration": )" +
         number_text(seconds) + "}]}";
}

struct Run {
  std::string configuration, load;
  int repetition;
  haptics::SessionResult result;
};

nlohmann::json run_json(const Run& r) {
  const auto& s = r.result.loop;
  const double seconds = s.achieved_rate_hz > 0.0 ? double(s.ticks) / s.achieved_rate_hz : 0.0;
  return {{"configuration", r.configuration},
          {"load", r.load},
          {"repetition", r.repetition},
          {"rate_hz", s.achieved_rate_hz},
          {"ticks", s.ticks},
          {"overruns", s.overruns},
          {"overruns_per_s", seconds > 0.0 ? double(s.overruns) / seconds : 0.0},
          {"realtime_priority", s.realtime_priority},
          {"watchdog_ticks", s.watchdog_ticks},
          {"min_delivered_force_ratio", r.result.felt.min_delivered_ratio},
          {"min_delivered_force_ratio_time", r.result.felt.min_delivered_ratio_time},
          {"max_tick_change_fraction", r.result.felt.max_tick_change_fraction},
          {"max_tick_change_time", r.result.felt.max_tick_change_time},
          {"max_force_jump_fraction", r.result.max_force_jump_fraction},
          {"cuts", r.result.cuts},
          {"cut_step_seconds", r.result.cut_step_seconds},
          {"cut_complete_seconds", r.result.cut_complete_seconds},
          {"cut_steps_waited", r.result.cut_steps_waited},
          {"peak_model_force", r.result.peak_force.empty() ? 0.0 : r.result.peak_force[0]}};
}

/// Where a session's cut step goes (issue 39, item 1): the script's cut steps taken as the session's
/// hook takes them (CutSystemUpdate: the surface step, the integration, CutTableStep's two phases), on
/// a thread with the session's background budget (cores - 1), the first response over the region
/// elements within the session's reach rule of the tools' press points, without the loop beside it.
nlohmann::json step_profile(const std::shared_ptr<const GreensTable>& table, const ActionScript& script) {
  const haptics::SessionOptions rule;
  std::vector<Eigen::Vector3d> points;
  double reach = rule.reach_margin;
  for (const Action& a : script.actions)
    if (a.type == ActionType::Press) {
      points.push_back(a.at);
      reach = std::max(reach, rule.tool_reach(script.tools[static_cast<std::size_t>(a.tool)].radius));
    }
  nlohmann::json steps = nlohmann::json::array();
  const haptics::BackgroundThreadBudget budget;  // the session's: OpenBLAS and OpenMP on cores - 1 threads
  const int threads = std::max(1, budget.threads());
  std::thread worker([&] {
    haptics::enter_background_thread(threads);
    CutSystemOptions options;
    options.background_refactor = false;  // as the session's hook
    CutSystemUpdate system(table, options);
    for (const Action& a : script.actions) {
      if (a.type != ActionType::Cut) continue;
      system.begin_cut();
      for (int k = 0; k < a.steps; ++k) {
        const auto t0 = SteadyClock::now();
        const CutSurfaceStep surface = system.cut_surface(a.from, a.direction);
        if (!surface.accepted) break;
        const double surface_s = seconds_since(t0);
        const std::shared_ptr<const GreensTable> current = system.table();
        CutChange change = integrate_cut_change(*current->mesh(), *surface.mesh, surface.delta, current->material(), current->quadrature(),
                                                current->gravity());
        const CutTableStep step(current, surface.mesh, surface.delta, std::move(change));
        const std::vector<Index> near = elements_within_reach(*surface.mesh, step.region(), points, reach);
        GreensTableUpdateResult first, complete;
        step.first_response(near, &first);
        const double first_s = seconds_since(t0);
        step.complete(&complete);
        const double complete_s = seconds_since(t0);
        steps.push_back({{"equations", surface.mesh->num_dofs()},
                         {"region_elements", step.region().size()},
                         {"reach_elements", near.size()},
                         {"changed_elements", surface.delta.modified.size() + surface.delta.added.size()},
                         {"surface_seconds", surface_s},
                         {"integration_seconds", complete.integration_seconds},
                         {"change_seconds", complete.change_seconds},
                         {"first_response_solve_columns", first.solve_columns},
                         {"solve_columns", complete.solve_columns},
                         {"solve_seconds", complete.solve_seconds},
                         {"correction_seconds", complete.correction_seconds},
                         {"snapshot_seconds", complete.snapshot_seconds},
                         {"gemm_seconds", complete.gemm_seconds},
                         {"finish_seconds", complete.finish_seconds},
                         {"first_response_seconds", first_s},
                         {"complete_seconds", complete_s},
                         {"rank", complete.rank}});
        if (!system.apply(surface).accepted) break;  // the next step starts from this one (untimed: the same update again)
      }
    }
  });
  worker.join();
  return {{"threads", threads}, {"reach_metres", reach}, {"tool_points", points.size()}, {"steps", steps}};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int repeat = 5;  // issue 37: a timing is a median of at least 5 runs
  std::string json_path, csv_dir;
  std::string scene_path = std::string(BEMSURG_EXAMPLES_DIR) + "/scenes/liver.json";
  std::string script_path = std::string(BEMSURG_EXAMPLES_DIR) + "/liver-cut-session.json";
  cli::OptionParser parser = bench::command_line(
      "bench_cut_continuity", "The force a hand feels while cut steps compute beside a held probe, before and after (docs/haptics.md).\n",
      quick, json_path);
  parser.value("--csv-dir", "DIR", csv_dir, "write the probe's force trace of each configuration's first run there");
  parser.value("--repeat", "N", repeat, "runs of each configuration, interleaved (default 5; --quick: 1)").between(1, 20);
  parser.value("--scene", "FILE", scene_path, "the organ scene (default examples/scenes/liver.json)");
  parser.value("--script", "FILE", script_path, "the session (default examples/liver-cut-session.json)");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (quick) repeat = 1;

  const auto t0 = std::chrono::steady_clock::now();
  const Scene scene = load_scene(scene_path);
  const ActionScript script = load_action_script(script_path);
  GreensTableOptions table_options;
  table_options.region = scene.operating_elements;
  auto mesh = std::make_shared<const TriangleMesh>(scene.problem.mesh);
  auto table = std::make_shared<const GreensTable>(
      GreensTable::compute(scene.problem.mesh, scene.problem.material, scene.problem.boundary_conditions, table_options));
  const double precompute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("bench_cut_continuity: %ld elements, %ld table columns, scene and table in %s s; %u cores\n",
              static_cast<long>(mesh->num_elements()), static_cast<long>(table->columns().cols()), fixed_text(precompute_s, 2).c_str(),
              std::thread::hardware_concurrency());

  auto session_options = [](bool after) {
    haptics::SessionOptions o;
    const haptics::SurfaceCuts cuts = haptics::surface_cuts();  // a fresh cutter per run, made ready as bemsurg session does
    o.cut_hook = cuts.hook;
    o.cut_prepare = cuts.prepare;
    if (!after) {
      o.background_steps = false;
      o.limit_background_threads = false;
      o.loop.blend_s = 0.0;
      o.first_response = false;  // one phase, as before issue 39
      o.loop.realtime_priority = 0;
    }
    return o;
  };
  std::vector<Run> runs;
  bool ok = true;
  auto run = [&](const std::string& configuration, const std::string& load, int rep, const ActionScript& s, bool after) {
    const BusyLoad busy(load == "loaded");
    ProbeTrace trace;
    haptics::Session session(mesh, table, s, session_options(after));
    runs.push_back({configuration, load, rep, session.run(&trace)});
    if (rep == 0 && !csv_dir.empty() && !trace.write(csv_dir + "/trace_" + configuration + "_" + load + ".csv")) ok = false;
  };
  // Each configuration `repeat` times, interleaved (a VM's stalls come and go): the summary takes
  // the median rate and overruns per second and the worst felt-force figures.
  const ActionScript air = load_action_script_from_string(air_script(script.duration), ".", "empty loop");
  for (const std::string& load : quick ? std::vector<std::string>{"quiet"} : std::vector<std::string>{"quiet", "loaded"})
    for (int rep = 0; rep < repeat; ++rep) {
      if (!quick) run("empty", load, rep, air, true);
      run("before", load, rep, script, false);
      run("after", load, rep, script, true);
    }
  if (!ok) {
    std::fprintf(stderr, "bench_cut_continuity: cannot write the traces into %s\n", csv_dir.c_str());
    return 1;
  }

  std::printf("%-8s %-7s %8s %9s %5s %9s %9s %9s %5s  %s\n", "config", "load", "rate Hz", "overrun/s", "prio", "min D/M %", "max dD %",
              "jump M %", "cuts", "cut steps (s)");
  nlohmann::json j_runs = nlohmann::json::array();
  for (const Run& r : runs) {
    const nlohmann::json j = run_json(r);
    j_runs.push_back(j);
    std::string steps;
    for (double s : r.result.cut_step_seconds) steps += fixed_text(s, 3) + " ";
    std::printf("%-8s %-7s %8s %9s %5d %9s %9s %9s %5d  %s\n", r.configuration.c_str(), r.load.c_str(),
                fixed_text(j["rate_hz"].get<double>(), 1).c_str(), fixed_text(j["overruns_per_s"].get<double>(), 2).c_str(),
                r.result.loop.realtime_priority, fixed_text(100.0 * r.result.felt.min_delivered_ratio, 1).c_str(),
                fixed_text(100.0 * r.result.felt.max_tick_change_fraction, 2).c_str(),
                fixed_text(100.0 * r.result.max_force_jump_fraction, 2).c_str(), r.result.cuts, steps.c_str());
  }
  nlohmann::json summary = nlohmann::json::array();
  for (const std::string configuration : {"empty", "before", "after"})
    for (const std::string load : {"quiet", "loaded"}) {
      std::vector<double> rate, overruns, ratio, change, steps, completes;
      for (const nlohmann::json& r : j_runs)
        if (r["configuration"] == configuration && r["load"] == load) {
          rate.push_back(r["rate_hz"]);
          overruns.push_back(r["overruns_per_s"]);
          ratio.push_back(r["min_delivered_force_ratio"]);
          change.push_back(r["max_tick_change_fraction"]);
          for (double x : r["cut_step_seconds"]) steps.push_back(x);
          for (double x : r["cut_complete_seconds"]) completes.push_back(x);
        }
      if (rate.empty()) continue;
      summary.push_back({{"configuration", configuration},
                         {"load", load},
                         {"runs", rate.size()},
                         {"rate_hz_median", bench::median(rate)},
                         {"rate_hz_min", *std::min_element(rate.begin(), rate.end())},
                         {"overruns_per_s_median", bench::median(overruns)},
                         {"min_delivered_force_ratio", *std::min_element(ratio.begin(), ratio.end())},
                         {"max_tick_change_fraction", *std::max_element(change.begin(), change.end())},
                         {"cut_step_seconds_median", steps.empty() ? 0.0 : bench::median(steps)},
                         {"cut_step_seconds_min", steps.empty() ? 0.0 : *std::min_element(steps.begin(), steps.end())},
                         {"cut_step_seconds_max", steps.empty() ? 0.0 : *std::max_element(steps.begin(), steps.end())},
                         {"cut_complete_seconds_median", completes.empty() ? 0.0 : bench::median(completes)},
                         {"cut_steps", steps.size()}});
      std::printf("summary %-7s %-7s %d runs: rate median %s Hz (min %s), overruns/s median %s, min D/M %s %%, max dD %s %%\n",
                  configuration.c_str(), load.c_str(), static_cast<int>(rate.size()), fixed_text(bench::median(rate), 1).c_str(),
                  fixed_text(*std::min_element(rate.begin(), rate.end()), 1).c_str(), fixed_text(bench::median(overruns), 2).c_str(),
                  fixed_text(100.0 * *std::min_element(ratio.begin(), ratio.end()), 1).c_str(),
                  fixed_text(100.0 * *std::max_element(change.begin(), change.end()), 2).c_str());
    }
  // The step's profile after the runs (a full run only: seconds per cut step, no loop beside it).
  const nlohmann::json profile = quick ? nlohmann::json::object() : step_profile(table, script);
  if (!quick)
    for (const nlohmann::json& p : profile["steps"])
      std::printf(
          "step profile (%d thread): n %ld, reach %ld of %ld elements: surface %s, integration %s, solves %s (%ld rhs, %ld in the "
          "first response), correction %s, table %s s; first response %s s, complete %s s\n",
          profile["threads"].get<int>(), p["equations"].get<long>(), p["reach_elements"].get<long>(), p["region_elements"].get<long>(),
          fixed_text(p["surface_seconds"].get<double>(), 3).c_str(), fixed_text(p["integration_seconds"].get<double>(), 3).c_str(),
          fixed_text(p["solve_seconds"].get<double>(), 3).c_str(), p["solve_columns"].get<long>(),
          p["first_response_solve_columns"].get<long>(), fixed_text(p["correction_seconds"].get<double>(), 3).c_str(),
          fixed_text(p["snapshot_seconds"].get<double>() + p["gemm_seconds"].get<double>() + p["finish_seconds"].get<double>(), 3).c_str(),
          fixed_text(p["first_response_seconds"].get<double>(), 3).c_str(), fixed_text(p["complete_seconds"].get<double>(), 3).c_str());
  std::vector<double> cut_times;
  for (const Action& a : script.actions)
    if (a.type == ActionType::Cut)
      for (int s = 0; s < a.steps; ++s) cut_times.push_back(a.time + s * a.step_interval);
  nlohmann::json out = {{"elements", mesh->num_elements()},
                        {"table_columns", table->columns().cols()},
                        {"precompute_seconds", precompute_s},
                        {"cores", std::thread::hardware_concurrency()},
                        {"blend_s", haptics::HapticLoopOptions{}.blend_s},
                        {"stale_after_s", haptics::HapticLoopOptions{}.stale_after_s},
                        {"cut_times", cut_times},
                        {"script_seconds", script.duration},
                        {"runs", j_runs},
                        {"summary", summary},
                        {"step_profile", profile}};
  return bench::write_json_file(json_path, out, "bench_cut_continuity") ? 0 : 1;
}
