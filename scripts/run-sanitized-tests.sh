#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer and runs it.
# Optimised (-O1 via RelWithDebInfo would be -O2; sanitizers stay accurate at both) so the
# numerical tests finish in minutes. Used by .ci/run as its second pass.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build-sanitize}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBEMSURG_SANITIZE=ON \
  -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=OFF -DBEMSURG_BUILD_EXAMPLES=OFF
cmake --build "$BUILD_DIR" -j"${JOBS:-2}"
cd "$BUILD_DIR"
# OpenMP's runtime keeps thread pools alive at exit; those are not leaks of ours.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --output-on-failure -j"${JOBS:-2}" --timeout 900
