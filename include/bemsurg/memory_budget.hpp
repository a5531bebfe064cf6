// bemsurg/memory_budget.hpp: how much memory a dense computation may take on this machine. The
// dense solve (solve_elastostatic) and the Green's table precomputation estimate their peak
// before allocating and refuse with ResourceError when it exceeds the default budget.
#pragma once

#include <string>

namespace bemsurg {

/// This machine's physical memory in bytes (sysconf), or 0 when it cannot be determined.
double physical_memory_bytes();

/// The default limit for one computation: 80 % of physical memory (4 GiB when unknown).
double default_memory_limit_bytes();

/// Asks the C library to keep freed large blocks for reuse instead of handing them back to the
/// system (glibc: mmap off for large requests, no trimming of the heap). A cut step builds a new
/// table snapshot (n x 3|region| doubles, hundreds of MB on a fine mesh) and frees the one before;
/// fresh pages cost a page fault each, and on a virtual machine those faults can take more time
/// than the step's arithmetic (benchmarks/bench_cut measures both; docs/cutting.md). The heap
/// then stays at its peak size. This changes the whole process, so
/// the library never calls it: programs that cut (bemsurg cut and session, the viewer, bench_cut) call it once
/// at start. Returns false where the C library has no such setting.
bool reuse_freed_memory();

/// Bytes as GiB with three significant digits, e.g. "1.27e+03 GiB" or "3.5 GiB", for messages.
std::string format_gib(double bytes);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/impl/memory_budget_impl.hpp"
#endif
