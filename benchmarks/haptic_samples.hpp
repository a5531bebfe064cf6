// haptic_samples.hpp: the raw per-tick samples bench_haptic_loop writes with --samples-dir (the
// benchmark report's CDFs, scripts/report/parts/haptic.py), recorded outside the haptic thread.
//   * tick jitter |actual period - nominal period| of every tick, from the loop's trace (one
//     TickSample per tick, drained on the simulation side by a SessionObserver): the same quantity
//     the loop's own histogram holds (HapticLoop::record_tick), so the haptic hot path gains
//     nothing; a tick the trace dropped ends the pair (no value across the gap);
//   * the bare-clock thread's longest gap within each 1 ms slot (what a 1 kHz tick in that slot
//     could have been delayed by whatever it computed; a slot inside a longer gap gets that gap).
//   * the force-computation time of every tick (TickSample::compute_us, from the same trace).
//
// Files: jitter.csv `source,configuration,value_us` (source session | empty_loop | bare_clock;
// configuration busy | sleep_spin for the loops, max_gap_per_1ms_slot for the bare clock),
// force_time.csv `source,configuration,value_us` (the loops' ticks) and
// quantiles.csv `source,configuration,metric,ticks,p50_us,p99_us,p999_us,max_us` (metric jitter |
// force: the loop's own LoopStatistics).
#pragma once

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "bemsurg/haptics/session.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::bench {

/// Collects |dt - nominal| per tick from the session's trace, on the simulation side's thread.
class JitterRecorder : public haptics::SessionObserver {
 public:
  JitterRecorder(double rate_hz, double expected_seconds) : nominal_(1.0 / rate_hz) {
    values_us_.reserve(static_cast<std::size_t>(expected_seconds * rate_hz * 2.0) + 1024);
    compute_us_.reserve(values_us_.capacity());
  }
  void on_sample(const haptics::TickSample& s) override {
    compute_us_.push_back(s.compute_us);
    if (have_last_ && s.tick == last_tick_ + 1) values_us_.push_back(std::abs((s.time - last_time_) - nominal_) * 1e6);
    have_last_ = true;
    last_tick_ = s.tick;
    last_time_ = s.time;
  }
  const std::vector<double>& values_us() const { return values_us_; }
  const std::vector<double>& compute_us() const { return compute_us_; }

 private:
  double nominal_;
  bool have_last_ = false;
  std::uint64_t last_tick_ = 0;
  double last_time_ = 0.0;
  std::vector<double> values_us_;
  std::vector<double> compute_us_;
};

/// The CSV files of --samples-dir, opened once; rows are appended per distribution.
class SampleFiles {
 public:
  explicit SampleFiles(const std::string& dir) {
    if (dir.empty()) return;
    jitter_.open(dir + "/jitter.csv");
    force_.open(dir + "/force_time.csv");
    quantiles_.open(dir + "/quantiles.csv");
    use_classic_locale(jitter_);
    use_classic_locale(force_);
    use_classic_locale(quantiles_);
    jitter_ << "source,configuration,value_us\n";
    force_ << "source,configuration,value_us\n";
    quantiles_ << "source,configuration,metric,ticks,p50_us,p99_us,p999_us,max_us\n";
  }
  bool enabled() const { return jitter_.is_open(); }
  bool good() const { return !enabled() || (jitter_.good() && force_.good() && quantiles_.good()); }
  void jitter(const char* source, const char* configuration, const std::vector<double>& values_us) {
    write(jitter_, source, configuration, values_us);
  }
  void force_time(const char* source, const char* configuration, const std::vector<double>& values_us) {
    write(force_, source, configuration, values_us);
  }
  void loop(const char* source, const char* configuration, const haptics::LoopStatistics& s) {
    if (!enabled()) return;
    row(source, configuration, "jitter", s.ticks, s.jitter_us);
    row(source, configuration, "force", s.ticks, s.force_us);
  }

 private:
  void write(std::ofstream& f, const char* source, const char* configuration, const std::vector<double>& values_us) {
    if (!enabled()) return;
    for (double v : values_us) f << source << ',' << configuration << ',' << v << '\n';
  }
  void row(const char* source, const char* configuration, const char* metric, std::uint64_t ticks, const haptics::Percentiles& p) {
    quantiles_ << source << ',' << configuration << ',' << metric << ',' << ticks << ',' << p.p50 << ',' << p.p99 << ',' << p.p999 << ','
               << p.max << '\n';
  }
  std::ofstream jitter_, force_, quantiles_;
};

}  // namespace bemsurg::bench
