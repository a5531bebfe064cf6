// bemsurg/dense_storage.hpp: large dense matrices whose storage asks the kernel for huge pages.
// A core helper: assembly (H, G, A*), the low-rank updated LU (solvers/) and the Green's table
// (presolution/) allocate with it, so it lives below all of them in the module order
// (docs/design.md, "Module order").
#pragma once

#include <Eigen/Core>
#if defined(__linux__)
#include <sys/mman.h>

#include <cstdint>
#endif

namespace bemsurg {

/// Large dense outputs (H, G: 8 (3E)^2 bytes each) are written once, right after allocation. With
/// 4 KiB pages that first touch costs one page fault per 4 KiB, and on virtual machines a fault
/// costs microseconds each, which for a matrix of a few hundred MB can exceed the integration that
/// fills it (benchmarks/bench_assembly measures it). Transparent huge pages take 512 times fewer
/// faults; Linux gives them to ranges that ask (madvise) when
/// /sys/kernel/mm/transparent_hugepage/enabled is [madvise] or [always]. Advice only: where it is
/// not available nothing changes. Call before the first write. From 2 MiB up: a cut step's
/// reaction rows are of that size and pay for their faults too (benchmarks/bench_cut).
inline void advise_huge_pages(double* data, Eigen::Index count) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::uintptr_t bytes = static_cast<std::uintptr_t>(count) * sizeof(double);
  if (data == nullptr || bytes < (std::uintptr_t(2) << 20)) return;  // less than one 2 MiB huge page
  const std::uintptr_t page = 4096, start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + page - 1) & ~(page - 1), end = (start + bytes) & ~(page - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)count;
#endif
}

/// A rows x cols matrix whose storage has been advised as above (entries uninitialised).
inline Eigen::MatrixXd large_dense_matrix(Eigen::Index rows, Eigen::Index cols) {
  Eigen::MatrixXd m(rows, cols);
  advise_huge_pages(m.data(), m.size());
  return m;
}

}  // namespace bemsurg
