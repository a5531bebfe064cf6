// Implementation of bemsurg/haptics/background_threads.hpp.
#include "bemsurg/haptics/background_threads.hpp"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bemsurg::haptics {

int background_thread_count(unsigned cores) noexcept {
  if (cores == 0) cores = std::thread::hardware_concurrency();
  return std::max(1, static_cast<int>(cores) - 1);
}

BackgroundThreadBudget::BackgroundThreadBudget(bool enabled) noexcept {
  if (!enabled) return;
  threads_ = background_thread_count();
  blas_.emplace(threads_);
#ifdef _OPENMP
  saved_omp_ = omp_get_max_threads();
  omp_set_num_threads(std::min(saved_omp_, threads_));
#endif
}

BackgroundThreadBudget::~BackgroundThreadBudget() {
  if (threads_ == 0) return;
  blas_.reset();
#ifdef _OPENMP
  if (saved_omp_ > 0) omp_set_num_threads(saved_omp_);
#endif
}

void enter_background_thread(int threads) noexcept {
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(std::min(threads, omp_get_max_threads()));
#else
  (void)threads;
#endif
}

}  // namespace bemsurg::haptics
