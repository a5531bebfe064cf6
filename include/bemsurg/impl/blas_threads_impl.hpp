// Implementation of bemsurg/blas_threads.hpp: the live caps under one mutex, the pool set to their
// minimum (the state is OpenBLAS's own, process-wide; this only orders the changes made to it).
#pragma once

#include <algorithm>
#include <map>
#include <mutex>

#include "bemsurg/config.hpp"

// OpenBLAS's thread controls, declared weak: present when the BLAS bemsurg links is OpenBLAS
// (Debian's default), null otherwise (reference BLAS, no pool to cap).
extern "C" {
void openblas_set_num_threads(int) __attribute__((weak));
int openblas_get_num_threads(void) __attribute__((weak));
}

namespace bemsurg {
namespace detail {

struct BlasCapState {
  std::mutex mutex;
  std::map<int, int> live;  // cap -> how many live caps ask for it
  int before = 0;           // the pool's size before the first live cap
};

BEMSURG_INLINE BlasCapState& blas_cap_state() {
  static BlasCapState state;
  return state;
}

BEMSURG_INLINE bool have_openblas_controls() { return openblas_set_num_threads != nullptr && openblas_get_num_threads != nullptr; }

}  // namespace detail

BEMSURG_INLINE int blas_threads() noexcept { return detail::have_openblas_controls() ? openblas_get_num_threads() : 0; }

BEMSURG_INLINE BlasThreadCap::BlasThreadCap(int threads) noexcept : threads_(threads) {
  if (threads_ <= 0 || !detail::have_openblas_controls()) return;
  detail::BlasCapState& s = detail::blas_cap_state();
  try {
    std::lock_guard<std::mutex> lock(s.mutex);
    if (s.live.empty()) s.before = openblas_get_num_threads();
    ++s.live[threads_];
    openblas_set_num_threads(std::min(s.before, s.live.begin()->first));
  } catch (...) {  // no memory for the map's node, or the mutex refused: no cap (slower, not wrong)
    threads_ = 0;
  }
}

BEMSURG_INLINE BlasThreadCap::~BlasThreadCap() {
  if (threads_ <= 0 || !detail::have_openblas_controls()) return;
  detail::BlasCapState& s = detail::blas_cap_state();
  const std::lock_guard<std::mutex> lock(s.mutex);  // locked once already by this cap: it does not throw here
  const auto it = s.live.find(threads_);
  if (it != s.live.end() && --it->second == 0) s.live.erase(it);
  openblas_set_num_threads(s.live.empty() ? s.before : std::min(s.before, s.live.begin()->first));
}

}  // namespace bemsurg
