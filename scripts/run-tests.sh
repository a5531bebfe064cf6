#!/usr/bin/env bash
# Installs the dependencies, builds bemsurg (Release, tests and benchmarks) and runs the whole
# test suite with ctest. This is README's test command and what .ci/run calls.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
# CI sets BEMSURG_WARNINGS_AS_ERRORS=ON; a newcomer's compiler may warn where GCC 12 does not.
# Everything builds as a unity build, test programs included (one translation unit per program,
# tests/CMakeLists.txt): each unit parses Eigen once per batch and instantiates the header-only
# core's templates once per program instead of once per file (docs/development.md, "CI, step by step").
# Built here is what ctest runs, and nothing else: not the viewer's window (BEMSURG_VIEWER_GUI=OFF;
# its tested core stays; run-demo.sh and check-viewer.sh build the window), and not the examples
# (BEMSURG_BUILD_EXAMPLES=OFF: header_only_cube, the header-only core's proof, is the one unit that
# compiles the whole core again, about 55 s of compile time; CI builds and runs the same program
# against the installed package, consumer_header_only, .ci/run step 2).
source scripts/support/build-generator.sh  # Ninja for a new tree when installed
build_generator "$BUILD_DIR"
cmake -S . -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=ON -DCMAKE_UNITY_BUILD=ON \
  -DBEMSURG_BUILD_EXAMPLES=OFF -DBEMSURG_VIEWER_GUI=OFF -DBEMSURG_WARNINGS_AS_ERRORS="${BEMSURG_WARNINGS_AS_ERRORS:-OFF}"
cmake --build "$BUILD_DIR" -j"${JOBS:-2}"
cd "$BUILD_DIR"
ctest --output-on-failure -j"${JOBS:-2}" --timeout 600
