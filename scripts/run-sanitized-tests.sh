#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer and assertions on (no
# NDEBUG: bemsurg's and Eigen's own checks, as a user's Debug build has them) and runs it.
# Optimised at -O1 with line tables only (-g1): stack traces keep file and line, sanitizers stay
# accurate, and the build takes about half the time of -O2 -g. The viewer's window is left out
# (BEMSURG_VIEWER_GUI=OFF): this tree runs the viewer's core tests, never the window.
# Used by .ci/run; docs/development.md says what it costs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build-sanitize}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DBEMSURG_SANITIZE=ON \
  -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=OFF -DBEMSURG_BUILD_EXAMPLES=OFF -DBEMSURG_VIEWER_GUI=OFF \
  -DBEMSURG_WARNINGS_AS_ERRORS=${BEMSURG_WARNINGS_AS_ERRORS:-OFF}
cmake --build "$BUILD_DIR" -j"${JOBS:-2}"
root=$PWD
cd "$BUILD_DIR"
# OpenMP's runtime keeps thread pools alive at exit; those are not leaks of ours.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
# Leaks inside Debian's libgmsh are its own (tests/support/lsan-suppressions.txt says which).
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/tests/support/lsan-suppressions.txt}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --output-on-failure -j"${JOBS:-2}" --timeout 900
