#!/usr/bin/env bash
# Issue 28's organ scenes in CI (docs/organs.md): for the liver-like and the kidney-like organ, a raw
# segmentation is generated (`bemsurg sample-segmentation`: ~100,000 triangles in mm, deliberately
# defective; never committed), `bemsurg prepare` must make it a valid body (checked from its report),
# and the scene that loads the raw file through "prepare" runs through solve, press, cut, session and
# the viewer's headless mode. The prepared mesh is cached after the first load (scene_prepare.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
OUT_DIR=${OUT_DIR:-out/check-organs}
CLI="$BUILD_DIR/bin/bemsurg"
VIEWER="$BUILD_DIR/bin/bemsurg-viewer"
[ -x "$CLI" ] || { echo "check-organs: $CLI was not built" >&2; exit 1; }
if [ -z "${DISPLAY:-}" ] && [ -z "${BEMSURG_CHECK_ORGANS_INNER:-}" ] && [ -x "$VIEWER" ]; then  # the viewer needs a display
  command -v xvfb-run >/dev/null || { echo "check-organs: no DISPLAY and no xvfb-run (Debian package xvfb)" >&2; exit 1; }
  export BEMSURG_CHECK_ORGANS_INNER=1
  exec xvfb-run -a -s "-screen 0 1280x800x24" bash "$0" "$@"
fi
rm -rf "$OUT_DIR"
mkdir -p "$OUT_DIR"
export BEMSURG_CACHE_DIR="$PWD/$OUT_DIR/cache"
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

for organ in liver kidney; do
  out="$OUT_DIR/$organ"
  scene="examples/scenes/${organ}_segmentation.json"
  script="examples/${organ}-segmentation-session.json"
  "$CLI" sample-segmentation "$organ" -o "examples/scenes/${organ}_segmentation.stl"
  "$CLI" prepare "examples/scenes/${organ}_segmentation.stl" --units mm -o "$out-prepared.obj" --report "$out-prepare.json" -q
  "$PY" - "$out-prepare.json" "$organ" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
d = j["defects"]
hierarchical = j["estimate"].get("hierarchical_memory_bytes") is not None
default = 6000 if hierarchical else 3000
checks = [
    ("defects found: self-intersection, non-manifold edge, hole, flipped and zero-area faces",
     d["self_intersections"] > 0 and d["non_manifold_edges"] > 0 and d["holes"] > 0 and d["flipped_faces"] > 0 and d["degenerate_faces"] > 0, d),
    ("rebuilt, the speck dropped", j["repairs"]["rebuilt"] and j["repairs"]["bodies_dropped"] == 1, j["repairs"]),
    # The default target follows the backend (docs/organs.md): 6,000 with hmat-oss, 3,000 without.
    (f"about the default target ({default:,} elements{', hierarchical backend' if hierarchical else ''})",
     j["remesh"]["target_elements"] == default and 0.83 * default <= j["output"]["elements"] <= 1.17 * default,
     (j["remesh"]["target_elements"], j["output"]["elements"])),
    ("Hausdorff distance under 2 % of the diagonal", j["hausdorff_relative"] < 0.02, j["hausdorff_relative"]),
    ("volume within 2 %", abs(j["volume_change"]) < 0.02, j["volume_change"]),
    ("in metres (under 0.3 m across)", max(j["input"]["size"]) < 0.3, j["input"]["size"]),
]
bad = [c for c in checks if not c[1]]
for what, ok, value in checks:
    print(f"check-organs: {sys.argv[2]} prepare: {'ok  ' if ok else 'FAIL'} {what}" + ("" if ok else f": {value}"))
sys.exit(1 if bad else 0)
PYEOF
  "$CLI" solve "$scene" -o "$out/solve" --quiet
  at=$("$PY" -c "import json; a=json.load(open('$script'))['actions']; print(','.join(map(str, a[0]['at'])), ','.join(map(str, a[0]['direction'])), ','.join(map(str, a[1]['from'])), ','.join(map(str, a[1]['direction'])))")
  read -r press_at press_dir cut_from cut_dir <<< "$at"
  "$CLI" press "$scene" --tool sphere:0.01 --at "$press_at" --direction "$press_dir" --depth 0.002 -o "$out/press" --quiet
  "$CLI" cut "$scene" --from "$cut_from" --direction "$cut_dir" --steps 2 -o "$out/cut" --quiet
  "$CLI" session "$scene" --script "$script" -o "$out/session" --quiet
  "$PY" - "$out" "$organ" <<'PYEOF'
import json, sys
out, organ = sys.argv[1], sys.argv[2]
force = json.load(open(f"{out}/press/force.json"))["force"]
cut = json.load(open(f"{out}/cut/report.json"))
session = json.load(open(f"{out}/session/report.json"))
fn = sum(f * f for f in force) ** 0.5
checks = [("press: a finite, nonzero force", 0.0 < fn < 1e3, force),
          ("cut: both steps made", len(cut["steps"]) == 2, len(cut["steps"])),
          ("session: both cut steps made", session["cuts"] == 2, session["cuts"])]
for what, ok, value in checks:
    print(f"check-organs: {organ}: {'ok  ' if ok else 'FAIL'} {what}: {value}")
sys.exit(0 if all(c[1] for c in checks) else 1)
PYEOF
  if [ -x "$VIEWER" ]; then
    "$VIEWER" --script "$script" --frames 60 --size 640x400 --screenshot "$out/viewer.png" > "$out/viewer.log" 2>&1 ||
      { cat "$out/viewer.log" >&2; echo "check-organs: FAIL: the viewer exited with an error on $organ" >&2; exit 1; }
    grep -q "cuts: 2 steps accepted" "$out/viewer.log" ||
      { cat "$out/viewer.log" >&2; echo "check-organs: FAIL: the viewer did not make both cut steps on $organ" >&2; exit 1; }
    echo "check-organs: $organ: ok   viewer headless: both cut steps, picture $out/viewer.png"
  fi
done
echo "check-organs: ok"
