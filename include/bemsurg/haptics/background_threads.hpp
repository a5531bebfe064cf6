// bemsurg/haptics/background_threads.hpp: the cores that seconds-long background work (a cut
// step's table update, a recomputed table) may use while a haptic loop runs, so that the haptic
// thread keeps one (docs/haptics.md, "Threads while a loop runs"). On a 2-core machine a cut
// step's dense algebra on both cores left the 1 kHz thread waiting for a core: 930-965 Hz and
// 4-7 times the overruns of a quiet run (issue 26). Background work therefore gets
// cores - 1 threads (at least one): OpenMP regions it starts, and OpenBLAS's pool, which is
// global to the process (its pthread build has no per-thread setting).
#pragma once

#include <optional>
#include <thread>

#include "bemsurg/blas_threads.hpp"

namespace bemsurg::haptics {

/// Threads for background work beside a haptic loop on a machine with `cores` cores: cores - 1,
/// at least 1 (0 = std::thread::hardware_concurrency()).
int background_thread_count(unsigned cores = 0) noexcept;

/// While it lives (a haptic loop runs): OpenBLAS's thread pool and the OpenMP threads of the
/// constructing thread are capped at background_thread_count(); the destructor restores both.
/// `enabled = false` changes nothing (the before/after benchmark's "before"). Not copyable.
/// \ingroup haptics
class BackgroundThreadBudget {
 public:
  explicit BackgroundThreadBudget(bool enabled = true) noexcept;
  ~BackgroundThreadBudget();
  BackgroundThreadBudget(const BackgroundThreadBudget&) = delete;
  BackgroundThreadBudget& operator=(const BackgroundThreadBudget&) = delete;
  /// The cap (threads a background worker should use), or 0 when disabled.
  int threads() const noexcept { return threads_; }

 private:
  int threads_ = 0;
  std::optional<BlasThreadCap> blas_;  // OpenBLAS's pool, with the other caps (bemsurg/blas_threads.hpp)
  int saved_omp_ = 0;
};

/// Called first on a background worker thread: its OpenMP regions use at most `threads` threads
/// (<= 0: unchanged). Its scheduling priority is left alone: lowered (nice + 10, tried), a cut step
/// beside a compile took 4-8 s instead of 0.8-1.6 s, and the SCHED_FIFO haptic thread does not need
/// it; where SCHED_FIFO is refused, nothing in the process can raise the haptic thread above other
/// programs (docs/haptics.md, "Threads while a loop runs").
void enter_background_thread(int threads) noexcept;

}  // namespace bemsurg::haptics
