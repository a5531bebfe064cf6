#!/usr/bin/env bash
# Installs the dependencies, builds bemsurg (Release, tests and benchmarks) and runs the whole
# test suite with ctest. This is README's test command and what .ci/run calls.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
# CI sets BEMSURG_WARNINGS_AS_ERRORS=ON; a newcomer's compiler may warn where GCC 12 does not.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=ON \
  -DBEMSURG_WARNINGS_AS_ERRORS="${BEMSURG_WARNINGS_AS_ERRORS:-OFF}"
cmake --build "$BUILD_DIR" -j"${JOBS:-2}"
cd "$BUILD_DIR"
ctest --output-on-failure -j"${JOBS:-2}" --timeout 600
