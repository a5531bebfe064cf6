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

/// Bytes as GiB with three significant digits, e.g. "1.27e+03 GiB" or "3.5 GiB", for messages.
std::string format_gib(double bytes);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#include "bemsurg/impl/memory_budget_impl.hpp"
