// bemsurg/blas_threads.hpp: caps on OpenBLAS's thread pool, which is global to the process (its
// pthread build has no per-thread setting). Two kinds of work want fewer BLAS threads than the
// machine has cores: background work beside a haptic loop (haptics/background_threads.hpp: the
// haptic thread keeps a core) and an H-LU, whose BLAS calls are on leaves of at most 120 rows, so
// a second thread only adds hand-offs (docs/solvers.md, "Threads": on 2 cores hmat-oss's H-LU of a
// 5,120-element body took 21.3 s with 2 BLAS threads and 15.6 s with 1). Caps nest and overlap
// across threads: while any cap lives, the pool has the smallest live cap (never more than it had
// before the first), and when the last one ends the pool gets back what it had. Where the BLAS is
// not OpenBLAS (no pool to cap), a cap changes nothing. Debian's default OpenBLAS is the pthread
// build, which this was measured on; its OpenMP build ties the setting to the calling thread's
// OpenMP threads, and a cap's restore then sets what the pool had, not what that thread had.
#pragma once

#include "bemsurg/config.hpp"

namespace bemsurg {

/// While it lives, OpenBLAS uses at most `threads` threads (<= 0: no cap). Not copyable.
/// \ingroup core
class BlasThreadCap {
 public:
  explicit BlasThreadCap(int threads) noexcept;
  ~BlasThreadCap();
  BlasThreadCap(const BlasThreadCap&) = delete;
  BlasThreadCap& operator=(const BlasThreadCap&) = delete;

 private:
  int threads_ = 0;
};

/// OpenBLAS's thread count now, or 0 where the BLAS is not OpenBLAS.
int blas_threads() noexcept;

}  // namespace bemsurg

#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/impl/blas_threads_impl.hpp"
#endif
