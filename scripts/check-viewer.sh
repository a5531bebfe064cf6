#!/usr/bin/env bash
# CI check of bemsurg-viewer's headless mode (docs/viewer.md "Checked in CI"): plays the prod-and-cut
# session examples/viewer-cut.json on the default model and checks three pictures by pixel
# differences inside the 3D view (the side panel and the colour bar are left out):
#   1. not blank: the last frame shows a model (>= 10 % of the view differs from the background
#      and it holds >= 50 distinct colours);
#   2. deformed: between frame 0 (self-weight only) and the last frame the colours of the model
#      itself (coloured by |u|; grey tool and background pixels excluded) change on >= 1 % of the view;
#   3. cut visible: between frame 35 (probe pressed and held, just before the cut starts at 1.2 s)
#      and the last frame (the same held probe, after the cut) >= 300 pixels change by more than
#      60 in some channel. Playback is deterministic, so without a cut these two frames are
#      identical pixel for pixel; the viewer must also report accepted cut steps.
# Runs itself under xvfb-run when there is no DISPLAY. Builds the viewer when it is missing.
# Exit 0 when all three hold; 1 otherwise, saying which failed. Pictures stay in OUT_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
OUT_DIR=${OUT_DIR:-out/check-viewer}
VIEWER="$BUILD_DIR/bin/bemsurg-viewer"

if [ -z "${DISPLAY:-}" ] && [ -z "${BEMSURG_CHECK_VIEWER_INNER:-}" ]; then
  command -v xvfb-run >/dev/null || { echo "check-viewer: no DISPLAY and no xvfb-run (Debian package xvfb)" >&2; exit 1; }
  export BEMSURG_CHECK_VIEWER_INNER=1
  exec xvfb-run -a -s "-screen 0 1280x800x24" bash "$0" "$@"
fi

if [ ! -x "$VIEWER" ]; then
  # README's test command leaves the window out of its tree (BEMSURG_VIEWER_GUI=OFF): turn it on.
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_VIEWER_GUI=ON >/dev/null
  cmake --build "$BUILD_DIR" -j"${JOBS:-2}" --target bemsurg_viewer
fi
[ -x "$VIEWER" ] || { echo "check-viewer: $VIEWER was not built (GLFW, OpenGL or imgui missing?)" >&2; exit 1; }

mkdir -p "$OUT_DIR"
rm -f "$OUT_DIR"/session*.png
start=$(date +%s%N)
"$VIEWER" --script examples/viewer-cut.json --frames 75 --shots 0,35 --size 1280x800 \
  --screenshot "$OUT_DIR/session.png" 2> "$OUT_DIR/viewer.log" || {
  cat "$OUT_DIR/viewer.log" >&2
  echo "check-viewer: FAIL: the viewer exited with an error" >&2
  exit 1
}
cat "$OUT_DIR/viewer.log"
end=$(date +%s%N)

# Debian's python3 (python3-pil, python3-numpy); the first python3 on PATH may lack them.
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3
"$PY" - "$OUT_DIR" "$OUT_DIR/viewer.log" <<'PYEOF'
import re, sys
import numpy as np
from PIL import Image

out, log = sys.argv[1], sys.argv[2]
def load(name):
    return np.asarray(Image.open(f"{out}/{name}").convert("RGB")).astype(np.int32)
first, before_cut, last = load("session-f0000.png"), load("session-f0035.png"), load("session.png")
# The 3D view: right of the side panel (390 px) and left of the colour bar (last 130 px).
view = (slice(0, last.shape[0]), slice(400, last.shape[1] - 130))
background = np.array([237, 240, 245])
failures = []

def region(img):
    return img[view]

# 1. not blank
v = region(last)
model = np.abs(v - background).max(axis=2) > 30
colours = len(np.unique(v.reshape(-1, 3), axis=0))
frac_model = model.mean()
print(f"check-viewer: last frame: {100 * frac_model:.1f} % of the view is model/tool, {colours} distinct colours")
if frac_model < 0.10 or colours < 50:
    failures.append("the last frame is blank (or nearly)")

# 2. deformed: colour change of model pixels (saturated colour-map pixels in both frames)
a, b = region(first), region(last)
def saturated(img):
    return (img.max(axis=2) - img.min(axis=2)) > 40
both = saturated(a) & saturated(b)
changed = (np.abs(a - b).max(axis=2) > 30) & both
frac_def = changed.mean()
print(f"check-viewer: deformation: the model's colours changed on {100 * frac_def:.2f} % of the view (frame 0 -> last)")
if frac_def < 0.01:
    failures.append("the model did not visibly deform between the first and the last frame")

# 3. cut visible: frame 35 (held probe, before the cut) vs last (held probe, after the cut)
c, d = region(before_cut), region(last)
diff = np.abs(c - d).max(axis=2) > 60
n = int(diff.sum())
text = open(log).read()
m = re.search(r"cuts: (\d+) steps accepted, (\d+) refused", text)
accepted = int(m.group(1)) if m else 0
print(f"check-viewer: cut: {n} pixels changed strongly between frame 35 and the last frame; {accepted} cut steps accepted")
if accepted < 1:
    failures.append("no cut step was accepted (" + (m.group(0) if m else "no cut summary") + ")")
if n < 300:
    failures.append("the cut is not visible (fewer than 300 pixels changed after it)")

if failures:
    for f in failures:
        print("check-viewer: FAIL: " + f, file=sys.stderr)
    sys.exit(1)
print("check-viewer: OK")
PYEOF
echo "check-viewer: viewer run took $(( (end - start) / 1000000 )) ms (pictures in $OUT_DIR)"
