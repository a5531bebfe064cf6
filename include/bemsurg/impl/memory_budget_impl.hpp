// Implementation of bemsurg/memory_budget.hpp (POSIX sysconf).
#pragma once

#include <unistd.h>

#include <sstream>

namespace bemsurg {

inline double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0.0;
  return double(pages) * double(page);
}

inline double default_memory_limit_bytes() {
  const double physical = physical_memory_bytes();
  if (physical <= 0.0) return 4.0 * 1024.0 * 1024.0 * 1024.0;
  return 0.8 * physical;
}

inline std::string format_gib(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / (1024.0 * 1024.0 * 1024.0) << " GiB";
  return s.str();
}

}  // namespace bemsurg
