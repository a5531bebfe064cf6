#!/usr/bin/env bash
# Profiles a clean Release build of README's test tree (library, CLI, tests, the benchmark ctest runs, examples,
# viewer): the wall time of the build and of each translation unit, heaviest first. The figures in
# docs/development.md come from it. Usage: scripts/profile-build.sh [BUILD_DIR] (default
# build-profile; removed first). Packages must be installed (scripts/setup-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build-profile}
rm -rf "$BUILD_DIR"
mkdir -p "$BUILD_DIR"
log="$(cd "$BUILD_DIR" && pwd)/compile-times.tsv"
: > "$log"
export BEMSURG_COMPILE_LOG="$log"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=ON \
  -DCMAKE_CXX_COMPILER_LAUNCHER="$PWD/scripts/support/time-compile.sh" > "$BUILD_DIR/configure.log"
s=$(date +%s)
cmake --build "$BUILD_DIR" -j"${JOBS:-2}" > "$BUILD_DIR/build.log"
e=$(date +%s)
total=$(awk -F'\t' '{ t += $1 } END { printf "%.0f", t }' "$log")
count=$(wc -l < "$log")
echo "profile-build: clean build $(( e - s )) s wall on ${JOBS:-2} jobs; $count translation units, $total s of compile time"
echo "profile-build: heaviest translation units (seconds, object):"
sort -rn "$log" | head -n "${TOP:-25}" | sed -E 's|CMakeFiles/[^/]*\.dir/||; s|^|  |'
