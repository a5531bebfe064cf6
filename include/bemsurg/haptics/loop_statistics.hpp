// bemsurg/haptics/loop_statistics.hpp: what a haptic loop reports about itself (achieved rate,
// period jitter, overruns, force-computation time, dropped packets) and the fixed-size histogram
// the haptic thread records into without allocating. Percentiles come from the histogram: 0.1 us
// bins up to 20 ms (one overflow bin beyond), so they are exact to 0.1 us below 20 ms.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace bemsurg::haptics {

/// A fixed-size histogram of durations in microseconds (0.1 us bins up to 20 ms, one overflow bin) that the haptic thread
/// records into without allocating; quantiles are exact to 0.1 us below 20 ms.
/// \ingroup haptics
class MicrosecondHistogram {
 public:
  static constexpr double kBinUs = 0.1;
  static constexpr std::size_t kBins = 200000;  // 0 .. 20 ms
  MicrosecondHistogram() : counts_(kBins + 1, 0) {}
  void add(double us) noexcept {
    std::size_t b = us <= 0.0 ? 0 : static_cast<std::size_t>(us / kBinUs);
    if (b > kBins) b = kBins;
    ++counts_[b];
    ++n_;
    if (us > max_) max_ = us;
  }
  std::uint64_t count() const { return n_; }
  double max() const { return max_; }
  /// The q-quantile (0 < q < 1), bin upper edge; 0 when empty.
  double quantile(double q) const {
    if (n_ == 0) return 0.0;
    const auto want = static_cast<std::uint64_t>(q * double(n_ - 1)) + 1;
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b <= kBins; ++b) {
      seen += counts_[b];
      if (seen >= want) return b == kBins ? max_ : (double(b) + 1.0) * kBinUs;
    }
    return max_;
  }
  void clear() {
    std::fill(counts_.begin(), counts_.end(), 0);
    n_ = 0;
    max_ = 0.0;
  }

 private:
  std::vector<std::uint64_t> counts_;
  std::uint64_t n_ = 0;
  double max_ = 0.0;
};

/// Median, 99th and 99.9th percentiles and maximum of a distribution of times (percentiles_of a MicrosecondHistogram).
/// \ingroup haptics
struct Percentiles {
  double p50 = 0.0, p99 = 0.0, p999 = 0.0, max = 0.0;
};
inline Percentiles percentiles_of(const MicrosecondHistogram& h) { return {h.quantile(0.5), h.quantile(0.99), h.quantile(0.999), h.max()}; }

/// A loop's report (docs/haptics.md, "Statistics"; the session's report.json carries it).
/// \ingroup haptics
struct LoopStatistics {
  double rate_hz = 0.0;  // requested
  double achieved_rate_hz = 0.0;
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;  // ticks that missed their slot (late by a period or longer than one)
  Percentiles jitter_us;       // |actual period - nominal period|
  Percentiles force_us;        // time to read devices, compute and write forces in one tick
  std::uint64_t dropped_packets = 0;
  std::uint64_t model_swaps = 0;     // new contact models taken between ticks
  std::uint64_t nan_guards = 0;      // non-finite forces replaced by the last good one
  std::uint64_t failed_steps = 0;    // contact steps that returned CapacityExceeded / Singular
  std::uint64_t watchdog_ticks = 0;  // ticks with the watchdog ramping (stale state, overruns, fault)
  std::uint64_t clamped_ticks = 0;   // ticks where the limiter changed the force
  std::uint64_t faults = 0;          // exceptions caught on the haptic thread (force zeroed)
  std::uint64_t trace_dropped = 0;   // trace samples lost because the reader fell behind
  int realtime_priority = 0;         // SCHED_FIFO priority the haptic thread got (0: normal)
};

}  // namespace bemsurg::haptics
