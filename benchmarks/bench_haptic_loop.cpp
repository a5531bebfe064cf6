// bench_haptic_loop: the haptic loop in real time during a scripted session of prodding (a sphere
// pressed and slid across the surface), pinching (pulled) and cutting, on a ~5,000-element model,
// while the simulation side computes the displacement field at the graphics rate (60 Hz) from the
// contact the loop publishes (docs/haptics.md). Reports the achieved rate, overruns, period jitter
// and force-computation time (p50, p99, p99.9), the largest force jump between consecutive
// samples of the sliding sphere, and the same at higher rates to find the highest that holds
// (zero overruns, p99.9 jitter <= 100 us).
//
// Platform baseline, measured in the same process before the session (issue 12, item 9: is a miss
// the machine's or bemsurg's?):
//   * bare clock: one thread at the loop's SCHED_FIFO priority reading steady_clock in a tight
//     loop for the script's duration; every gap between consecutive reads is time the thread did
//     not run. Gaps >= 1 ms are ticks a 1 kHz loop would have missed whatever it computed;
//   * empty loop: the same Session / HapticLoop machinery, same rate, settings and duration, with
//     the tools moving in the air far above the body (no contact, graphics_hz 0, no cuts), so the
//     loop has nothing to compute.
// The session and the empty loop run with two spin settings: the default sleep-then-spin
// (`--spin-us`, 150 us) and "busy" (spin >= the period: the thread never sleeps, a whole core).
//
// The compliance table is synthetic: the Boussinesq half-space surface compliance between element
// centroids (a uniformly loaded disc of the element's area for the self term), built directly in
// the table's column layout for the top-face region where the tools act. The loop's cost depends
// on n, the contact set and the table's layout, not on how the table was computed, and the BEM
// precomputation of 5,000 elements (15,000 equations, ~5 GB while assembling) is measured in
// bench_contact / bench_assembly, not here. The cut is a stand-in too: a new table snapshot (the
// old one copied and softened by 2 %) built on the simulation side and swapped in between ticks.
//
// usage: bench_haptic_loop [--quick] [--json PATH] [--spin-us US] [--samples-dir DIR]
//   --spin-us: how long the loop spins before each deadline instead of sleeping in the default
//   configuration (default 150 us); --samples-dir: write the raw per-tick jitter of the sessions and
//   empty loops, the bare clock's longest gap per 1 ms slot and the loops' quantiles as CSV
//   (haptic_samples.hpp says what the files hold; the benchmark report draws their CDFs)
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bemsurg/haptics/session.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bench_support.hpp"
#include "haptic_samples.hpp"
#include "support/half_space_table.hpp"

using namespace bemsurg;
using Vec3 = Eigen::Vector3d;

namespace {

using Model = haptics::HalfSpaceBlock;

/// Full: ~5,000 elements, 1 mm elements under the tools; quick: ~1,000, 4 mm. 100 kPa, nu 0.45:
/// newton-level forces at millimetres.
Model build_model(bool quick) {
  const Material material{1.0e5, 0.45, 1000.0};
  return quick ? haptics::half_space_block(0.004, 0.025, 0.008, 0.012, material)
               : haptics::half_space_block(0.001, 0.015, 0.008, 0.012, material);
}

std::string script_text(double rate_hz, double scale, bool cuts) {
  // Times scaled by `scale` (the quick run is shorter). Sphere: R = 10 mm, pressed 1 mm over
  // 0.3 s, then slid 12 mm along x at constant depth; pinch: grabs, pulls up 1 mm, lets go; blade: cuts.
  auto t = [&](double x) { return number_text(x * scale); };
  const double slide = 1.2 * scale;  // seconds for 12 mm
  std::string s = R"({"format": "bemsurg-actions", "version": 1, "rate_hz": )" + number_text(rate_hz) +
                  R"(, "capacity_rows": 600,
  "tools": [{"name": "probe", "shape": "sphere", "radius": 0.010},
            {"name": "grasper", "shape": "pinch", "radius": 0.0015},
            {"name": "scalpel", "shape": "blade"}],
  "actions": [
    {"time": 0.0, "tool": "probe", "type": "press", "at": [-0.006, -0.002, 0.02], "direction": [0, 0, -1], "depth": 0.001, "duration": )" +
                  t(0.3) + R"(},
    {"time": )" + t(0.3) +
                  R"(, "tool": "probe", "type": "move", "to": [0.006, -0.002, )" + number_text(0.010 - 0.001) + R"(], "duration": )" +
                  number_text(slide) + R"(},
    {"time": )" + t(0.3) +
                  R"(, "tool": "grasper", "type": "pinch", "at": [0.0, 0.006, 0.02], "direction": [0, 0, -1]},
    {"time": )" + t(0.3) +
                  R"(, "tool": "grasper", "type": "move", "to": [0.0, 0.006, 0.001], "duration": )" + t(0.5) + R"(},
    {"time": )" + t(1.0) +
                  R"(, "tool": "grasper", "type": "release"})";
  if (cuts)
    s += R"(,
    {"time": )" +
         t(0.5) +
         R"(, "tool": "scalpel", "type": "cut", "from": [-0.004, 0.008, 0.0], "direction": [1, 0, 0], "steps": 2, "step_interval": )" +
         t(0.3) + "}";
  s += "]}";
  return s;
}

/// Continuity (docs/haptics.md): the sphere alone, pressed 1 mm, then slid 10 mm along x at
/// constant depth at 10 mm/s (the top surface is flat, so constant depth is constant z).
std::string slide_script() {
  return R"({"format": "bemsurg-actions", "version": 1, "rate_hz": 1000, "capacity_rows": 600,
  "tools": [{"name": "probe", "shape": "sphere", "radius": 0.010}],
  "actions": [
    {"time": 0.0, "tool": "probe", "type": "press", "at": [-0.005, -0.002, 0.02], "direction": [0, 0, -1], "depth": 0.001, "duration": 0.3},
    {"time": 0.3, "tool": "probe", "type": "move", "to": [0.005, -0.002, 0.009], "duration": 1.0}
  ]})";
}

/// The empty loop's script: the same three tools (so the same channels and devices), each moving
/// slowly in the air 200 mm above the top face (z = 0) for `duration` seconds: no contact, nothing
/// for the loop to compute beyond reading devices and writing zero forces.
std::string air_script(double rate_hz, double duration) {
  const std::string d = number_text(duration);
  return R"({"format": "bemsurg-actions", "version": 1, "rate_hz": )" + number_text(rate_hz) + R"(, "duration": )" + d +
         R"(, "capacity_rows": 600,
  "tools": [{"name": "probe", "shape": "sphere", "radius": 0.010, "start": [-0.006, -0.002, 0.2]},
            {"name": "grasper", "shape": "pinch", "radius": 0.0015, "start": [0.0, 0.006, 0.2]},
            {"name": "scalpel", "shape": "blade", "start": [-0.004, 0.008, 0.2]}],
  "actions": [
    {"time": 0.0, "tool": "probe", "type": "move", "to": [0.006, -0.002, 0.2], "duration": )" +
         d + R"(},
    {"time": 0.0, "tool": "grasper", "type": "move", "to": [0.0, 0.006, 0.21], "duration": )" +
         d + R"(},
    {"time": 0.0, "tool": "scalpel", "type": "move", "to": [0.004, 0.008, 0.2], "duration": )" +
         d + R"(}
  ]})";
}

/// What a thread that only reads the clock sees of the machine: every gap between consecutive
/// reads is time it did not run (preempted, vCPU descheduled by the host, throttled).
struct BareClock {
  double seconds = 0.0;
  int realtime_priority = 0;  // SCHED_FIFO priority granted (0: refused, normal priority)
  std::uint64_t reads = 0;
  std::uint64_t gaps_over_20us = 0, gaps_over_100us = 0, gaps_over_1ms = 0;
  double max_gap_us = 0.0;
  /// 1 kHz slots that fell entirely inside a gap (sum of floor(gap / 1 ms)); the loop counts one
  /// overrun per such gap (it skips missed slots rather than racing), so gaps_over_1ms is the
  /// comparable figure for "overruns", this one for "ticks not rendered".
  std::uint64_t slots_lost_1khz = 0;
  std::vector<std::pair<double, double>> long_gaps;  // (start s, length ms) of the first gaps >= 1 ms
  /// With record_slots: per 1 ms slot, the longest gap ending in it (a slot wholly inside a gap
  /// gets that gap): how late a 1 kHz tick in that slot could have started.
  std::vector<double> slot_max_gap_us;
};

BareClock bare_clock(double seconds, int priority, bool record_slots) {
  BareClock r;
  r.seconds = seconds;
  r.long_gaps.reserve(64);
  // Reserved up front: the timing thread must not allocate (no push_back past the capacity).
  if (record_slots) r.slot_max_gap_us.reserve(static_cast<std::size_t>(seconds * 1000.0) + 16);
  std::thread thread([&] {
    if (priority > 0) {  // as HapticLoop::run does
      sched_param p{};
      p.sched_priority = priority;
      if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0) r.realtime_priority = priority;
    }
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const auto end = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    auto prev = t0;
    std::int64_t slot = 0;
    double slot_max = 0.0;
    std::vector<double>& slots = r.slot_max_gap_us;
    for (;;) {
      const auto now = Clock::now();
      ++r.reads;
      const double gap = std::chrono::duration<double, std::micro>(now - prev).count();
      if (gap > 20.0) {
        ++r.gaps_over_20us;
        if (gap > 100.0) ++r.gaps_over_100us;
        if (gap >= 1000.0) {
          ++r.gaps_over_1ms;
          r.slots_lost_1khz += static_cast<std::uint64_t>(gap / 1000.0);
          if (r.long_gaps.size() < r.long_gaps.capacity())
            r.long_gaps.emplace_back(std::chrono::duration<double>(prev - t0).count(), gap / 1000.0);
        }
        r.max_gap_us = std::max(r.max_gap_us, gap);
      }
      if (record_slots) {
        const std::int64_t s = (now - t0) / std::chrono::milliseconds(1);
        if (s != slot) {
          if (slots.size() < slots.capacity()) slots.push_back(slot_max);
          for (std::int64_t k = slot + 1; k < s && slots.size() < slots.capacity(); ++k) slots.push_back(gap);
          slot = s;
          slot_max = 0.0;
        }
        slot_max = std::max(slot_max, gap);
      }
      prev = now;
      if (now >= end) break;
    }
  });
  thread.join();
  return r;
}

/// A kernel setting as a number (-1 when it cannot be read): the RT bandwidth limit lets SCHED_FIFO
/// threads run sched_rt_runtime_us of every sched_rt_period_us and keeps the rest for normal
/// threads, so a thread that never sleeps at SCHED_FIFO can lose (period - runtime) at a time
/// when normal threads are waiting on its CPU (50 ms per second by default).
long read_proc_number(const char* path) {
  std::FILE* f = std::fopen(path, "r");
  if (!f) return -1;
  long v = -1;
  if (std::fscanf(f, "%ld", &v) != 1) v = -1;
  std::fclose(f);
  return v;
}

nlohmann::json to_json(const haptics::Percentiles& p) { return {{"p50", p.p50}, {"p99", p.p99}, {"p999", p.p999}, {"max", p.max}}; }

/// The loop figures the baseline comparison needs; overruns also per second of loop time, since a
/// session waiting for its cuts runs longer than its script (and than the baselines).
nlohmann::json loop_json(const haptics::LoopStatistics& s, double spin_us) {
  const double seconds = s.achieved_rate_hz > 0.0 ? double(s.ticks) / s.achieved_rate_hz : 0.0;
  return {{"spin_us", spin_us},
          {"realtime_priority", s.realtime_priority},
          {"ticks", s.ticks},
          {"seconds", seconds},
          {"rate_hz", s.achieved_rate_hz},
          {"overruns", s.overruns},
          {"overruns_per_s", seconds > 0.0 ? double(s.overruns) / seconds : 0.0},
          {"jitter_us", to_json(s.jitter_us)},
          {"force_us", to_json(s.force_us)}};
}

double overruns_per_s(const haptics::LoopStatistics& s) {
  return s.ticks > 0 ? double(s.overruns) * s.achieved_rate_hz / double(s.ticks) : 0.0;
}

/// The session's excess over the empty loop with the same settings: what bemsurg's work (contact
/// forces, model swaps, the simulation side's cuts and field updates on the other core) adds.
nlohmann::json excess_json(const haptics::LoopStatistics& session, const haptics::LoopStatistics& empty) {
  return {{"overruns_per_s", overruns_per_s(session) - overruns_per_s(empty)},
          {"jitter_us",
           {{"p50", session.jitter_us.p50 - empty.jitter_us.p50},
            {"p99", session.jitter_us.p99 - empty.jitter_us.p99},
            {"p999", session.jitter_us.p999 - empty.jitter_us.p999}}},
          {"force_us",
           {{"p50", session.force_us.p50 - empty.force_us.p50},
            {"p99", session.force_us.p99 - empty.force_us.p99},
            {"p999", session.force_us.p999 - empty.force_us.p999}}}};
}

void print_loop_row(const char* name, const haptics::LoopStatistics& s) {
  std::printf("  %-28s %6lu %7s %5lu %7s  %7s %7s %8s %8s  %6s %6s %6s\n", name, static_cast<unsigned long>(s.ticks),
              fixed_text(double(s.ticks) / std::max(1.0, s.achieved_rate_hz), 2).c_str(), static_cast<unsigned long>(s.overruns),
              fixed_text(overruns_per_s(s), 2).c_str(), fixed_text(s.jitter_us.p50, 1).c_str(), fixed_text(s.jitter_us.p99, 1).c_str(),
              fixed_text(s.jitter_us.p999, 1).c_str(), fixed_text(s.jitter_us.max, 0).c_str(), fixed_text(s.force_us.p50, 1).c_str(),
              fixed_text(s.force_us.p99, 1).c_str(), fixed_text(s.force_us.p999, 1).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path;
  double spin_us = 150.0;
  std::string samples_dir;
  cli::OptionParser parser =
      bench::command_line("bench_haptic_loop",
                          "The haptic loop's rate, jitter and force time in a scripted session against the empty loop\n"
                          "(docs/haptics.md).\n",
                          quick, json_path);
  parser.value("--spin-us", "US", spin_us, "microseconds the loop spins before each tick instead of sleeping").at_least(0.0);
  parser.value("--samples-dir", "DIR", samples_dir,
               "write the per-tick jitter and force time and the bare clock's gaps there as CSV (haptic_samples.hpp)");
  double session_seconds = 0.0;
  parser
      .value("--session-seconds", "S", session_seconds,
             "stretch the scripted session (and the empty loop and bare clock beside it) to S seconds, so that tail "
             "quantiles rest on enough ticks (the report: 60 s, 60,000 ticks, so p99.9 is 60 of them)")
      .at_least(0.0)
      .default_text("0: the script's own length (about 1.6 s; --quick: half)");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  bench::SampleFiles samples(samples_dir);
  if (!samples.good()) {
    std::fprintf(stderr, "bench_haptic_loop: cannot write into %s\n", samples_dir.c_str());
    return 1;
  }
  const Model model = build_model(quick);
  std::printf("bench_haptic_loop: %ld elements, %ld table columns (%s MB), fine edge %s mm\n",
              static_cast<long>(model.mesh->num_elements()), static_cast<long>(model.table->columns().cols()),
              fixed_text(double(model.table->bytes()) / 1e6, 0).c_str(), fixed_text(model.fine_edge * 1e3, 1).c_str());
  double scale = quick ? 0.5 : 1.0;
  if (session_seconds > 0.0)  // every time in the script scales with `scale`
    scale = session_seconds / load_action_script_from_string(script_text(1000.0, 1.0, true), ".", "bench").duration;

  haptics::SessionOptions options;
  options.graphics_hz = 60.0;
  options.loop.realtime_priority = 80;  // SCHED_FIFO when the machine allows it (reported)
  options.loop.spin_us = spin_us;
  options.cut_hook = [](const haptics::CutRequest& r) {
    // Stand-in for the cutting module: a new, slightly softer snapshot built here, off the loop.
    auto t = std::make_shared<const GreensTable>(r.table->key(), r.table->region(), r.table->base_displacement(), r.table->base_traction(),
                                                 r.table->base_kinds(), Eigen::MatrixXd(1.02 * r.table->columns()));
    return haptics::CutResult{r.mesh, t};
  };
  // "Busy": spin longer than the period, so HapticLoop::run never sleeps (twice the period, so a
  // deadline pushed back by a skipped slot does not make it sleep either).
  auto busy_spin_us = [](double rate) { return 2.0e6 / rate; };

  auto run = [&](double rate, bool with_cuts, double spin, double script_scale, haptics::SessionObserver* observer = nullptr) {
    haptics::SessionOptions o = options;
    o.loop.spin_us = spin;
    const ActionScript script = load_action_script_from_string(script_text(rate, script_scale, with_cuts), ".", "bench");
    haptics::Session session(model.mesh, model.table, script, o);
    return session.run(observer);
  };
  const double script_seconds = load_action_script_from_string(script_text(1000.0, scale, true), ".", "bench").duration;
  auto run_empty = [&](double rate, double spin, haptics::SessionObserver* observer) {
    haptics::SessionOptions o = options;
    o.loop.spin_us = spin;
    o.graphics_hz = 0.0;
    o.cut_hook = nullptr;
    haptics::Session session(model.mesh, model.table, load_action_script_from_string(air_script(rate, script_seconds), ".", "empty"), o);
    return session.run(observer);
  };

  // 1. Platform baseline, before the session: the bare clock, then the empty loop in both spin
  //    settings, each for the session script's duration.
  const BareClock bare = bare_clock(script_seconds, options.loop.realtime_priority, samples.enabled());
  const double busy_us = busy_spin_us(1000.0);
  // The per-tick jitter, when asked for (--samples-dir): from the trace, on the simulation side.
  bench::JitterRecorder rec_empty_default(1000.0, script_seconds), rec_empty_busy(1000.0, script_seconds);
  bench::JitterRecorder rec_default(1000.0, 2.0 * script_seconds), rec_busy(1000.0, 2.0 * script_seconds);
  auto recorder = [&](bench::JitterRecorder& r) { return samples.enabled() ? &r : nullptr; };
  const haptics::SessionResult empty_default = run_empty(1000.0, spin_us, recorder(rec_empty_default));
  const haptics::SessionResult empty_busy = run_empty(1000.0, busy_us, recorder(rec_empty_busy));
  if (empty_default.loop.faults != 0 || empty_busy.loop.faults != 0 || empty_default.models_built < 1) {
    std::fprintf(stderr, "bench_haptic_loop: the empty loop did not run cleanly\n");
    return 1;
  }

  // 2. The session at 1 kHz in real time, sleep-then-spin (the library default) and busy.
  const haptics::SessionResult main_default = run(1000.0, true, spin_us, scale, recorder(rec_default));
  const haptics::SessionResult main_busy = run(1000.0, true, busy_us, scale, recorder(rec_busy));
  samples.jitter("bare_clock", "max_gap_per_1ms_slot", bare.slot_max_gap_us);
  samples.jitter("empty_loop", "sleep_spin", rec_empty_default.values_us());
  samples.jitter("empty_loop", "busy", rec_empty_busy.values_us());
  samples.jitter("session", "sleep_spin", rec_default.values_us());
  samples.jitter("session", "busy", rec_busy.values_us());
  samples.force_time("empty_loop", "sleep_spin", rec_empty_default.compute_us());
  samples.force_time("empty_loop", "busy", rec_empty_busy.compute_us());
  samples.force_time("session", "sleep_spin", rec_default.compute_us());
  samples.force_time("session", "busy", rec_busy.compute_us());
  samples.loop("empty_loop", "sleep_spin", empty_default.loop);
  samples.loop("empty_loop", "busy", empty_busy.loop);
  samples.loop("session", "sleep_spin", main_default.loop);
  samples.loop("session", "busy", main_busy.loop);
  if (!samples.good()) {
    std::fprintf(stderr, "bench_haptic_loop: writing the samples into %s failed\n", samples_dir.c_str());
    return 1;
  }

  // Which configuration the issue's top-level keys report. Decided once from measurements (docs/
  // haptics.md, "Measured": medians of 3 full runs), not per run, so the keys mean the same thing
  // in every run: busy. It is clearly better on p99 jitter (session 17 us against 488 us on the
  // quiet machine, 10 against 535 us under load: a thread that sleeps on this VM wakes up late, up
  // to a period, while the simulation side works or the machine is busy) and also has fewer
  // overruns (6 against 11; 5 against 16). Its price: a whole core, and a SCHED_FIFO thread that
  // never sleeps meets the kernel's RT bandwidth limit (one ~50 ms stall per second while a normal
  // thread waits for its CPU). The sleep-then-spin figures are reported beside it.
  const bool report_busy = true;
  const haptics::SessionResult& main = report_busy ? main_busy : main_default;
  const haptics::SessionResult& empty_main = report_busy ? empty_busy : empty_default;
  const double main_spin_us = report_busy ? busy_us : spin_us;
  const auto& s = main.loop;

  std::printf("haptic thread SCHED_FIFO priority: %d (0: refused, normal priority); bare clock thread: %d\n", s.realtime_priority,
              bare.realtime_priority);
  const long rt_runtime_us = read_proc_number("/proc/sys/kernel/sched_rt_runtime_us");
  const long rt_period_us = read_proc_number("/proc/sys/kernel/sched_rt_period_us");
  std::printf("kernel RT bandwidth: sched_rt_runtime_us %ld of sched_rt_period_us %ld (-1: unlimited / unreadable)\n", rt_runtime_us,
              rt_period_us);
  std::printf(
      "platform baseline, bare clock (%s s, %s M reads): gaps > 20 us %lu, > 100 us %lu, >= 1 ms %lu "
      "(1 kHz ticks it would have missed; %lu slots lost), largest %s us\n",
      fixed_text(bare.seconds, 2).c_str(), fixed_text(double(bare.reads) / 1e6, 1).c_str(), static_cast<unsigned long>(bare.gaps_over_20us),
      static_cast<unsigned long>(bare.gaps_over_100us), static_cast<unsigned long>(bare.gaps_over_1ms),
      static_cast<unsigned long>(bare.slots_lost_1khz), fixed_text(bare.max_gap_us, 0).c_str());
  if (!bare.long_gaps.empty()) {
    std::printf("  gaps >= 1 ms (start s: length ms):");
    for (const auto& g : bare.long_gaps) std::printf(" %s:%s", fixed_text(g.first, 3).c_str(), fixed_text(g.second, 2).c_str());
    std::printf("\n");
  }
  std::printf("1 kHz, %s s of script      %6s %7s %5s %7s  %-34s  %s\n", fixed_text(script_seconds, 2).c_str(), "ticks", "loop s", "over",
              "over/s", "jitter p50 / p99 / p99.9 / max us", "force p50 / p99 / p99.9 us");
  char label[64];
  std::snprintf(label, sizeof label, "empty loop, spin %s us", fixed_text(spin_us, 0).c_str());
  print_loop_row(label, empty_default.loop);
  std::snprintf(label, sizeof label, "session, spin %s us", fixed_text(spin_us, 0).c_str());
  print_loop_row(label, main_default.loop);
  std::snprintf(label, sizeof label, "empty loop, busy (%s us)", fixed_text(busy_us, 0).c_str());
  print_loop_row(label, empty_busy.loop);
  std::snprintf(label, sizeof label, "session, busy (%s us)", fixed_text(busy_us, 0).c_str());
  print_loop_row(label, main_busy.loop);
  auto print_excess = [](const char* name, const haptics::LoopStatistics& a, const haptics::LoopStatistics& e) {
    std::printf("  session - empty loop, %-6s overruns/s %s, jitter p99 %s / p99.9 %s us, force p99.9 %s us\n", name,
                bench::signed_fixed_text(overruns_per_s(a) - overruns_per_s(e), 2).c_str(),
                bench::signed_fixed_text(a.jitter_us.p99 - e.jitter_us.p99, 1).c_str(),
                bench::signed_fixed_text(a.jitter_us.p999 - e.jitter_us.p999, 1).c_str(),
                bench::signed_fixed_text(a.force_us.p999 - e.force_us.p999, 1).c_str());
  };
  print_excess("spin:", main_default.loop, empty_default.loop);
  print_excess("busy:", main_busy.loop, empty_busy.loop);
  std::printf(
      "top-level figures: %s; session: %lu model swaps, %d cuts, %d field updates (median %s ms), "
      "largest force jump %s %%\n",
      report_busy ? "busy" : "sleep-then-spin", static_cast<unsigned long>(s.model_swaps), main.cuts, main.field_updates,
      fixed_text(main.field_ms.p50, 2).c_str(), fixed_text(100.0 * main.max_force_jump_fraction, 2).c_str());

  // 3. Continuity on the virtual clock (no timing noise, no other tool letting go): the sphere
  //    alone sliding at 10 mm/s at constant depth 1 mm.
  haptics::SessionOptions slide_options = options;
  slide_options.virtual_clock = true;
  haptics::Session slide(model.mesh, model.table, load_action_script_from_string(slide_script(), ".", "slide"), slide_options);
  const haptics::SessionResult det = slide.run();
  std::printf(
      "sliding sphere (R 10 mm, depth 1 mm, 10 mm/s, virtual clock): largest force jump between consecutive 1 kHz "
      "samples %s %% at t = %s s (peak force %s N, %d contact models)\n",
      fixed_text(100.0 * det.max_force_jump_fraction, 3).c_str(), fixed_text(det.max_force_jump_time, 3).c_str(),
      fixed_text(det.peak_force[0], 3).c_str(), det.models_built);
  // 4. Higher rates, shorter, in the reported configuration: the highest that holds (zero
  //    overruns, p99.9 jitter <= 100 us). --quick runs them at half its script length, to stay a
  //    few seconds with the baselines and both spin settings.
  const double rates_scale = quick ? 0.25 : 1.0;  // the rate sweep keeps the script's own length
  nlohmann::json rates = nlohmann::json::array();
  double highest = s.overruns == 0 && s.jitter_us.p999 <= 100.0 ? 1000.0 : 0.0;
  for (double rate : {2000.0, 5000.0, 10000.0}) {
    const haptics::SessionResult r = run(rate, false, report_busy ? busy_spin_us(rate) : spin_us, rates_scale);
    const bool holds = r.loop.overruns == 0 && r.loop.jitter_us.p999 <= 100.0;
    std::printf("  %5s Hz: achieved %s Hz, %lu overruns, jitter p99.9 %s us, force p99.9 %s us%s\n", fixed_text(rate, 0).c_str(),
                fixed_text(r.loop.achieved_rate_hz, 1).c_str(), static_cast<unsigned long>(r.loop.overruns),
                fixed_text(r.loop.jitter_us.p999, 1).c_str(), fixed_text(r.loop.force_us.p999, 1).c_str(), holds ? " (holds)" : "");
    if (holds && rate > highest) highest = rate;
    rates.push_back({{"requested_hz", rate},
                     {"rate_hz", r.loop.achieved_rate_hz},
                     {"overruns", r.loop.overruns},
                     {"jitter_us", {{"p50", r.loop.jitter_us.p50}, {"p99", r.loop.jitter_us.p99}, {"p999", r.loop.jitter_us.p999}}},
                     {"force_us", {{"p50", r.loop.force_us.p50}, {"p99", r.loop.force_us.p99}, {"p999", r.loop.force_us.p999}}},
                     {"holds", holds}});
  }
  std::printf("highest rate that holds: %s Hz\n", fixed_text(highest, 0).c_str());

  nlohmann::json out;
  out["benchmark"] = "bench_haptic_loop";
  out["quick"] = quick;
  out["elements"] = model.mesh->num_elements();
  out["fine_element_edge_m"] = model.fine_edge;
  // The issue's keys (item 9), for the reported configuration ("reported_configuration").
  out["rate_hz"] = s.achieved_rate_hz;
  out["overruns"] = s.overruns;
  out["jitter_us"] = {{"p50", s.jitter_us.p50}, {"p99", s.jitter_us.p99}, {"p999", s.jitter_us.p999}, {"max", s.jitter_us.max}};
  out["force_us"] = {{"p50", s.force_us.p50}, {"p99", s.force_us.p99}, {"p999", s.force_us.p999}, {"max", s.force_us.max}};
  out["max_force_jump_fraction"] = det.max_force_jump_fraction;  // the sliding sphere (item 6)
  out["sliding_speed_m_per_s"] = 0.010;
  out["sliding_depth_m"] = 0.001;
  out["sphere_radius_m"] = 0.010;
  out["max_force_jump_fraction_session"] = main.max_force_jump_fraction;  // includes the pinch letting go
  out["realtime_priority"] = s.realtime_priority;
  out["spin_us"] = main_spin_us;
  out["reported_configuration"] = report_busy ? "busy" : "sleep_spin";
  out["model_swaps"] = s.model_swaps;
  out["cuts"] = main.cuts;
  out["field_updates"] = main.field_updates;
  out["field_ms_median"] = main.field_ms.p50;
  out["watchdog_ticks"] = s.watchdog_ticks;
  out["failed_steps"] = s.failed_steps;
  out["higher_rates"] = rates;
  out["highest_rate_hz_holding"] = highest;
  out["script_seconds"] = script_seconds;
  // Both spin settings, each with its own empty loop and the session's excess over it.
  out["configurations"] = {{"sleep_spin",
                            {{"session", loop_json(main_default.loop, spin_us)},
                             {"empty_loop", loop_json(empty_default.loop, spin_us)},
                             {"excess_over_empty_loop", excess_json(main_default.loop, empty_default.loop)},
                             {"cuts", main_default.cuts}}},
                           {"busy",
                            {{"session", loop_json(main_busy.loop, busy_us)},
                             {"empty_loop", loop_json(empty_busy.loop, busy_us)},
                             {"excess_over_empty_loop", excess_json(main_busy.loop, empty_busy.loop)},
                             {"cuts", main_busy.cuts}}}};
  nlohmann::json long_gaps = nlohmann::json::array();
  for (const auto& g : bare.long_gaps) long_gaps.push_back({{"start_s", g.first}, {"length_ms", g.second}});
  out["platform_baseline"] = {{"bare_clock",
                               {{"seconds", bare.seconds},
                                {"realtime_priority", bare.realtime_priority},
                                {"reads", bare.reads},
                                {"gaps_over_20us", bare.gaps_over_20us},
                                {"gaps_over_100us", bare.gaps_over_100us},
                                {"gaps_over_1ms", bare.gaps_over_1ms},
                                {"max_gap_us", bare.max_gap_us},
                                {"missed_ticks_1khz", bare.gaps_over_1ms},
                                {"slots_lost_1khz", bare.slots_lost_1khz},
                                {"long_gaps", long_gaps},
                                {"sched_rt_runtime_us", rt_runtime_us},
                                {"sched_rt_period_us", rt_period_us}}},
                              {"empty_loop", loop_json(empty_main.loop, main_spin_us)}};
  out["excess_over_empty_loop"] = excess_json(s, empty_main.loop);
  if (!json_path.empty() && !bench::write_json_file(json_path, out, "bench_haptic_loop")) return 1;
  const bool ok = main_default.loop.ticks > 0 && main_busy.loop.ticks > 0 && main_default.loop.faults == 0 && main_busy.loop.faults == 0 &&
                  main_default.cuts == 2 && main_busy.cuts == 2;
  if (!ok)
    std::fprintf(stderr, "bench_haptic_loop: a session did not run as scripted (faults %lu / %lu, cuts %d / %d)\n",
                 static_cast<unsigned long>(main_default.loop.faults), static_cast<unsigned long>(main_busy.loop.faults), main_default.cuts,
                 main_busy.cuts);
  return ok ? 0 : 1;
}
