#!/usr/bin/env bash
# Builds the threaded parts with ThreadSanitizer and runs the tests that start threads: the haptic
# loop, the UDP bridge and the force limiter (all of test_haptics), the background refactorisation
# swapped in under a cut (test_cutting), the session command with its real-time haptic thread
# (test_cli's session cases, the CLI itself instrumented) and the viewer's model worker (all of
# test_viewer_core). The single-threaded cases of those programs (cut algebra, solve, press) run
# in the ASan tree; under TSan they would cost minutes and find nothing it looks for.
#
# OpenMP and OpenBLAS run one thread each: libgomp and OpenBLAS are not instrumented, so their
# barriers would look like races to TSan (37 false reports in the assembly's OpenMP loop with two
# threads). With one thread their parallel regions run on the calling thread, and every report
# left is about bemsurg's own threads. No suppressions are needed.
# Used by .ci/run; docs/development.md says what it costs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build-tsan}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DBEMSURG_SANITIZE_THREAD=ON \
  -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=OFF -DBEMSURG_BUILD_EXAMPLES=OFF -DBEMSURG_VIEWER_GUI=OFF \
  -DBEMSURG_WITH_REMESHER=OFF -DBEMSURG_WARNINGS_AS_ERRORS=${BEMSURG_WARNINGS_AS_ERRORS:-OFF}
programs=(test_haptics test_cutting test_cli test_viewer_core)
cmake --build "$BUILD_DIR" -j"${JOBS:-2}" --target "${programs[@]}" bemsurg_cli
cd "$BUILD_DIR"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
pattern='^(test_haptics:|test_viewer_core:|test_cutting:a background refactorisation|test_cli:bemsurg session)'
ctest --output-on-failure --no-tests=error -j"${JOBS:-2}" --timeout 900 -R "$pattern"
