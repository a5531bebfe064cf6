#!/usr/bin/env bash
# Builds the tests under a sanitizer and runs them. Used by .ci/run; docs/development.md says what
# each pass costs. Optimised at -O1 with line tables only (-g1): stack traces keep file and line,
# sanitizers stay accurate, and the build takes about half the time of -O2 -g. UndefinedBehaviorSanitizer
# runs its arithmetic checks (CMakeLists.txt says which four pointer checks are left out, and why). The viewer's window
# is left out (BEMSURG_VIEWER_GUI=OFF): these trees run the viewer's core tests, never the window.
#
#   scripts/run-sanitized-tests.sh [address]   AddressSanitizer + UndefinedBehaviorSanitizer over
#       the suite, with assertions on (no NDEBUG: bemsurg's and Eigen's own checks, as a user's
#       Debug build has them), less two things the Release run covers: mesh preparation's CGAL file
#       (built without CGAL, the prepare cases skip) and 11 slow studies (listed below).
#   scripts/run-sanitized-tests.sh thread      ThreadSanitizer over the tests that start threads:
#       the haptic loop, the UDP bridge and the force limiter (all of test_haptics), the background
#       refactorisation swapped in under a cut (test_cutting), the session command with its
#       real-time haptic thread (test_cli's session cases but the two that check a script's depths
#       and a table file's region, the CLI itself instrumented) and the viewer's model worker (all
#       of test_viewer_core). Their single-threaded cases run in the
#       address pass; under TSan they would cost minutes and find nothing it looks for. OpenMP and
#       OpenBLAS run one thread each: libgomp and OpenBLAS are not instrumented, so their barriers
#       would look like races (37 false reports in the assembly's OpenMP loop with two threads);
#       with one thread their regions run on the calling thread, and every report left is about
#       bemsurg's own threads. No suppressions are needed.
# Both trees leave MPI out (-DBEMSURG_WITH_MPI=OFF: Open MPI's own allocations and progress threads
# are not ours to chase; docs/distributed.md): the MPI cases skip there, and the refusal without MPI
# runs instead.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-address}
case "$mode" in
  address) sanitizer=(-DBEMSURG_SANITIZE=ON -DBEMSURG_WITH_PREPARE=OFF); default_dir=build-sanitize ;;
  thread) sanitizer=(-DBEMSURG_SANITIZE_THREAD=ON -DBEMSURG_WITH_REMESHER=OFF); default_dir=build-tsan ;;
  *) echo "run-sanitized-tests: unknown mode '$mode' (expected address or thread)" >&2; exit 2 ;;
esac
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-$default_dir}
# Unity build (the libraries, the CLI and the viewer's core in batches of 8 files, each test program as
# one unit, tests/CMakeLists.txt): these trees are built once per CI run and never edited in, and
# batching saves parsing Eigen and nlohmann-json, and instantiating the header-only core, again per file.
source scripts/support/build-generator.sh  # Ninja for a new tree when installed
build_generator "$BUILD_DIR"
cmake -S . -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" "${sanitizer[@]}" -DCMAKE_UNITY_BUILD=ON \
  -DBEMSURG_BUILD_TESTS=ON -DBEMSURG_BUILD_BENCHMARKS=OFF -DBEMSURG_BUILD_EXAMPLES=OFF -DBEMSURG_VIEWER_GUI=OFF \
  -DBEMSURG_WARNINGS_AS_ERRORS="${BEMSURG_WARNINGS_AS_ERRORS:-OFF}" -DBEMSURG_WITH_MPI=OFF
root=$PWD
if [ "$mode" = address ]; then
  cmake --build "$BUILD_DIR" -j"${JOBS:-2}"
  cd "$BUILD_DIR"
  # OpenMP's runtime keeps thread pools alive at exit; those are not leaks of ours.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
  # Leaks inside Debian's libgmsh are its own (tests/support/lsan-suppressions.txt says which).
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/tests/support/lsan-suppressions.txt}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  # Convergence studies that repeat, at more sizes, code paths the rest of the suite already runs
  # under this sanitizer (contact, linear elements, the fast assembly, the graded remesh, the
  # quadrature cost refusal): 125 s of the pass's CPU for nothing it looks for
  # (docs/development.md). The Release run has them all.
  heavy='test_contact:sphere: Hertz force|test_contact:frictionless flat punch converges'
  heavy+='|test_bem:linear elements: refining either half|test_bem:linear elements, Kelvin box'
  heavy+='|test_bem:linear elements, hanging bar|test_kernels:fast assembly equals the reference on a hollow sphere'
  heavy+='|test_mesh:In the operating region a graded brain answers'
  heavy+='|test_kernels:fast assembly equals the reference on a graded box|test_bem:ruinous quadrature options are refused'
  heavy+='|test_cli:linear elements fed at their nodes'
  # Issue 38's dense solves of a hung liver and the cut ball's and brain's remeshes for the area
  # figures: the conforming split, the rule pipeline and the planar regions run here in the
  # lighter cases beside them.
  heavy+='|test_io:A conform rule holds its region|test_io:refine_rim refines along'
  heavy+='|test_mesh:A graded remesh keeps the flat face of a cut ball|test_mesh:A graded remesh of the brain keeps its underside'
  # The hierarchical backend's accuracy studies (1,280 elements, dense and H-LU: the solve at two
  # tolerances, the table, two cuts): its block callbacks, the table's solve and a cut on a kept
  # H-LU run here in test_cli's smaller hmatrix cases and the 320-element refactorisation case;
  # linear elements' blocks (the 320-element comparison, 2,880 unknowns) in test_cli's 80-element one.
  heavy+='|test_solvers:the hierarchical backend solves a body resting|test_solvers:a table on the hierarchical backend'
  heavy+='|test_solvers:linear elements on the hierarchical backend'
  ctest --output-on-failure -j"${JOBS:-2}" --timeout 900 -E "$heavy"
else
  cmake --build "$BUILD_DIR" -j"${JOBS:-2}" --target test_haptics test_cutting test_cli test_viewer_core bemsurg_cli
  cd "$BUILD_DIR"
  export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
  export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
  # Two session cases check what a script and a table file may be (the table's region, the press
  # depth's range) with a virtual clock: the address pass runs them; here they cost 52 s of CPU,
  # a third of the pass's ctest, almost all of it their tables' dense algebra under instrumentation.
  ctest --output-on-failure --no-tests=error -j"${JOBS:-2}" --timeout 900 \
    -R '^(test_haptics:|test_viewer_core:|test_cutting:a background refactorisation|test_cli:bemsurg session)' \
    -E '^test_cli:bemsurg session (computes its table on the scene|checks each press depth)'
fi
