#!/usr/bin/env bash
# The checks that keep the tree's shape (issue 23; docs/design.md, "Module order";
# docs/development.md, "Structure checks"). Fast (seconds), no build needed; .ci/run runs it first.
#   1. the module graph from the #include lines (scripts/module-graph.py): no cycle, no edge against
#      the module order, the include rules of docs/design.md §1 (private src/ headers, deprecated
#      paths, what tests, benchmarks and examples may include), the header-only modules' impl/
#      headers compiled by their <module>_definitions.cpp and nothing of theirs defined elsewhere
#      but the documented compiled parts, both header lists of every module header equal to its
#      folder, and \ingroup <module> on every public class, struct and enum;
#   2. no source file in include/, src/ or examples/ over 600 lines;
#   3. no function over 100 lines without a `// long:` comment saying why
#      (scripts/support/long-functions.py);
#   4. the C++ sources formatted by .clang-format (Debian's clang-format 14);
#   5. every benchmark program either run by a part of the report (scripts/report/) or listed in
#      benchmarks/CMakeLists.txt's BEMSURG_BENCHMARKS_OUTSIDE_REPORT, which ctest smoke-runs: the
#      quick report in CI is the only run the others get.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
# report FINDINGS HEADER OK: the findings (one indented line each) under HEADER on stderr and a
# failure, or OK on stdout when there are none.
report() {
  if [ -n "$1" ]; then
    echo "check-structure: $2" >&2
    printf '%s' "$1" >&2
    status=1
  else
    echo "check-structure: $3"
  fi
}

python3 scripts/module-graph.py || status=1

# The file lists come from git; an empty list (git refusing the checkout, say) is a failure, not
# a pass with nothing checked.
sources_list=$(mktemp)
trap 'rm -f "$sources_list"' EXIT
git ls-files -co --exclude-standard include src examples tests benchmarks | grep -E '\.(hpp|cpp|h)$' > "$sources_list" || true
if [ ! -s "$sources_list" ]; then
  echo "check-structure: git lists no C++ source file; cannot check (is this a git checkout git trusts?)" >&2
  exit 1
fi

too_long=""
while read -r f; do
  case "$f" in include/* | src/* | examples/*) ;; *) continue ;; esac
  [ -f "$f" ] || continue
  n=$(wc -l < "$f")
  if [ "$n" -gt 600 ]; then too_long+="  $f: $n lines"$'\n'; fi
done < "$sources_list"
report "$too_long" "files over 600 lines (split them by job):" "no source file over 600 lines"

if [ -f scripts/support/long-functions.py ]; then
  python3 scripts/support/long-functions.py include src examples || status=1
fi

outside=$(sed -n 's/^set(BEMSURG_BENCHMARKS_OUTSIDE_REPORT \(.*\))$/\1/p' benchmarks/CMakeLists.txt)
unrun=""
for src in benchmarks/bench_*.cpp; do
  name=$(basename "$src" .cpp)
  if grep -qw "$name" <<< "$outside"; then
    if grep -rqw "$name" scripts/report; then unrun+="  $name: run by the report, yet listed as outside it"$'\n'; fi
  elif ! grep -rqw "$name" scripts/report; then
    unrun+="  $name: no part of scripts/report/ runs it and no smoke entry does"$'\n'
  fi
done
report "$unrun" "benchmark programs CI would run never or twice (benchmarks/CMakeLists.txt, BEMSURG_BENCHMARKS_OUTSIDE_REPORT):" \
  "every benchmark program runs in the quick report or as a ctest smoke entry"

format=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$format" ]; then
  echo "check-structure: clang-format not found (scripts/setup-deps.sh installs it)" >&2
  status=1
else
  mapfile -t sources < <(git ls-files include src examples tests benchmarks | grep -E '\.(hpp|cpp|h)$')
  if [ "${#sources[@]}" -eq 0 ]; then
    echo "check-structure: no tracked source to check the format of" >&2
    exit 1
  fi
  if "$format" --style=file --dry-run --Werror "${sources[@]}" 2> /tmp/bemsurg-format.log; then
    echo "check-structure: ${#sources[@]} files formatted as .clang-format says"
  else
    echo "check-structure: files not formatted (run: $format -i --style=file <file>):" >&2
    grep -oE '^[^:]+\.(hpp|cpp|h)' /tmp/bemsurg-format.log | sort -u | sed 's/^/  /' >&2
    status=1
  fi
fi
exit $status
