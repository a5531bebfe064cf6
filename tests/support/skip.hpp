// tests/support/skip.hpp: a test that cannot run in this build ends its process with exit code 77,
// which ctest reports as skipped (SKIP_RETURN_CODE in tests/CMakeLists.txt), never as passed.
// ctest runs each test case in a process of its own, so this skips exactly one case; a whole
// program run by hand stops at the first skipped case and says why.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace bemsurg::testing {

constexpr int kSkipReturnCode = 77;

inline void skip_unless(bool condition, const char* why) {
  if (condition) return;
  std::printf("SKIPPED: %s\n", why);
  std::fflush(stdout);
  std::_Exit(kSkipReturnCode);
}

}  // namespace bemsurg::testing
