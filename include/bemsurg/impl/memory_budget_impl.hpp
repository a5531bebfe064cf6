// Implementation of bemsurg/memory_budget.hpp (POSIX sysconf).
#pragma once

#include "bemsurg/config.hpp"
#include "bemsurg/number_text.hpp"

#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace bemsurg {

BEMSURG_INLINE double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0.0;
  return double(pages) * double(page);
}

BEMSURG_INLINE double default_memory_limit_bytes() {
  const double physical = physical_memory_bytes();
  if (physical <= 0.0) return 4.0 * 1024.0 * 1024.0 * 1024.0;
  return 0.8 * physical;
}

BEMSURG_INLINE bool reuse_freed_memory() {
#if defined(__GLIBC__)
  // M_MMAP_MAX 0: large requests come from the heap, so a freed table's pages are reused by the
  // next one; M_TRIM_THRESHOLD: never give the top of the heap back (glibc mallopt(3)).
  const bool ok = mallopt(M_MMAP_MAX, 0) == 1;
  return mallopt(M_TRIM_THRESHOLD, 0x7fffffff) == 1 && ok;
#else
  return false;
#endif
}

BEMSURG_INLINE std::string format_gib(double bytes) { return general_text(bytes / (1024.0 * 1024.0 * 1024.0), 3) + " GiB"; }

}  // namespace bemsurg
