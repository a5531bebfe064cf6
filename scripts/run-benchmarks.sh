#!/usr/bin/env bash
# The benchmark report (docs/benchmarks.md, docs/report.md): builds what it needs, runs the
# benchmark programs part by part, writes their CSV under DIR, draws the charts with Debian's
# matplotlib and writes DIR/report.md.
#
#   scripts/run-benchmarks.sh [--quick] [--out DIR] [--build DIR] [--only PART] [--publish] [--render-only]
#
#   --quick     small runs of every part (about 4 minutes on 2 cores once built; CI runs it)
#   --out DIR   where results, charts and report.md go (default results/, not committed)
#   --build DIR reuse an existing Release tree (default: configure and build build-bench/)
#   --only PART run one part (chart family) and redraw the report from what DIR holds
#   --publish   with a full run: copy report.md and its charts to docs/report.md, docs/images/report/
#   --render-only  run nothing: redraw the charts and report.md from DIR's data (with --publish:
#               only when DIR holds a full run of every part without a failure)
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0 out=results build="" only="" publish=0 render_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --out) out=${2:?--out needs a folder}; shift ;;
    --build) build=${2:?--build needs a folder}; shift ;;
    --only) only=${2:?--only needs a part name}; shift ;;
    --publish) publish=1 ;;
    --render-only) render_only=1 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run-benchmarks: unknown option '$1' (--help lists them)" >&2; exit 2 ;;
  esac
  shift
done
if [ "$publish" = 1 ] && { [ "$quick" = 1 ] || [ -n "$only" ]; }; then
  echo "run-benchmarks: --publish takes a full run of every part (not --quick, not --only)" >&2
  exit 2
fi

if [ "$publish" = 1 ] && [ -n "$(git status --porcelain --untracked-files=no)" ]; then
  # Checked again by the driver; here so that nothing is built or run first (docs/benchmarks.md).
  echo "run-benchmarks: --publish needs a clean tree: commit or stash the changes to tracked files first" >&2
  exit 2
fi
bash scripts/setup-deps.sh > /dev/null
start=$(date +%s)
if [ "$render_only" = 1 ]; then
  :  # nothing to build or run
elif [ -z "$build" ]; then
  build=build-bench
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_BUILD_TESTS=OFF -DBEMSURG_BUILD_BENCHMARKS=ON \
    -DBEMSURG_WARNINGS_AS_ERRORS="${BEMSURG_WARNINGS_AS_ERRORS:-OFF}" > /dev/null
fi
if [ "$render_only" = 1 ]; then
  build=${build:-build-bench}
elif ! grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "run-benchmarks: $build is not a configured Release tree (timings of another build type mislead)" >&2
  exit 2
else
  cmake --build "$build" -j"${JOBS:-2}" --target bemsurg_benchmarks
  echo "run-benchmarks: build took $(( $(date +%s) - start )) s"
fi

args=(--out "$out" --build "$build")
[ "$quick" = 1 ] && args+=(--quick)
[ -n "$only" ] && args+=(--only "$only")
[ "$render_only" = 1 ] && args+=(--render-only)
[ "$publish" = 1 ] && args+=(--require-complete)
# Debian's python3 (python3-matplotlib): another python3 may come first on PATH.
status=0
/usr/bin/python3 scripts/report/make_report.py "${args[@]}" || status=$?
echo "run-benchmarks: finished in $(( $(date +%s) - start )) s (status $status)"
[ "$status" = 0 ] || exit "$status"

if [ "$publish" = 1 ]; then
  rm -rf docs/images/report docs/report-data
  mkdir -p docs/images/report docs/report-data
  cp "$out"/images/*.png docs/images/report/
  sed 's#](images/#](images/report/#g' "$out/report.md" > docs/report.md
  # The data behind every chart and table (docs/benchmarks.md, "Checking a figure"): each part's CSV
  # and JSON, the parts' provenance (status.json) and the machine (machine.json). Not published: the
  # logs, the CalculiX reference cache, and meshes (peer/surface.stl), which `--only peer` remakes.
  (cd "$out" && find . \( -path ./cache -o -path ./logs -o -path ./images \) -prune -o -type f \( -name '*.csv' -o -name '*.json' \) -print) |
    while read -r f; do
      mkdir -p "docs/report-data/$(dirname "$f")"
      cp "$out/$f" "docs/report-data/$f"
    done
  # Per-tick samples (60 s of haptic ticks) are large: files over 1 MB are kept gzipped, and the
  # report reads FILE.csv.gz where FILE.csv is missing (report_lib.read_csv).
  find docs/report-data -name '*.csv' -size +1M -exec gzip -9 -n {} +
  echo "run-benchmarks: published docs/report.md, docs/images/report/ and docs/report-data/ ($(du -sh docs/report-data | cut -f1))"
fi
