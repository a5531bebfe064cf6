// bemsurg/timing.hpp: wall-clock intervals for the timings that reports and benchmarks carry
// (assembly, factorisation, solve). One steady clock for the whole library.
#pragma once

#include <chrono>

namespace bemsurg {

using SteadyClock = std::chrono::steady_clock;

/// Seconds from `start` to `end`.
inline double seconds_between(SteadyClock::time_point start, SteadyClock::time_point end) {
  return std::chrono::duration<double>(end - start).count();
}

/// Seconds elapsed since `start` on the steady clock.
inline double seconds_since(SteadyClock::time_point start) { return std::chrono::duration<double>(SteadyClock::now() - start).count(); }

}  // namespace bemsurg
