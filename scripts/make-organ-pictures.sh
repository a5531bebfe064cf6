#!/usr/bin/env bash
# Remakes the pictures of docs/organs.md, none by hand:
#   docs/images/organ-prepare.png   the raw liver segmentation (its defects marked), the mesh
#                                   `bemsurg prepare` makes of it and the mesh the scene solves
#                                   (matplotlib, scripts/support/organ-pictures.py);
#   docs/images/organ-liver.png     the headless viewer playing examples/liver-segmentation-session.json
#                                   (frame 45 of 60);
#   docs/images/organ-kidney.png    the same for examples/kidney-segmentation-session.json.
# The raw segmentations are generated (`bemsurg sample-segmentation`, not committed). Screenshots are
# shrunk to 960 x 600 and every picture is reduced to a palette (dithered), as make-viewer-screenshot.sh
# does, so each committed file stays under ~120 kB. Runs under xvfb-run when there is no DISPLAY.
# About a minute on the 2-core VM (60 s measured; the viewer precomputes each scene's table).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
CLI="$BUILD_DIR/bin/bemsurg"
VIEWER="$BUILD_DIR/bin/bemsurg-viewer"
for exe in "$CLI" "$VIEWER"; do
  [ -x "$exe" ] || { echo "make-organ-pictures: build bemsurg_cli and bemsurg_viewer first ($exe missing)" >&2; exit 1; }
done
if [ -z "${DISPLAY:-}" ] && [ -z "${BEMSURG_ORGAN_PICTURES_INNER:-}" ]; then
  export BEMSURG_ORGAN_PICTURES_INNER=1
  exec xvfb-run -a -s "-screen 0 1280x800x24" bash "$0" "$@"
fi
OUT=out/organ-pictures
mkdir -p "$OUT" docs/images
export BEMSURG_CACHE_DIR="$PWD/$OUT/cache"

for organ in liver kidney; do
  "$CLI" sample-segmentation "$organ" -o "examples/scenes/${organ}_segmentation.stl" --quiet
done
"$CLI" prepare examples/scenes/liver_segmentation.stl --units mm -o "$OUT/liver-prepared.obj" --quiet
"$CLI" solve examples/scenes/liver_segmentation.json -o "$OUT/liver-solve" --quiet
/usr/bin/python3 scripts/support/organ-pictures.py examples/scenes/liver_segmentation.stl "$OUT/liver-prepared.obj" \
  "$OUT/liver-solve/solved_mesh.obj" examples/scenes/liver_segmentation.json docs/images/organ-prepare.png

for organ in liver kidney; do
  "$VIEWER" --script "examples/${organ}-segmentation-session.json" --frames 60 --shots 45 \
    --screenshot "$OUT/$organ-viewer.png" 2> "$OUT/$organ-viewer.log"
  # Frame 45 (t = 1.5 s): the probe pressed 2 mm in and both cut steps made; frame 60 is after the release.
  /usr/bin/python3 - "$OUT/$organ-viewer-f0045.png" "docs/images/organ-$organ.png" <<'PYEOF'
import sys
from PIL import Image
im = Image.open(sys.argv[1]).convert("RGB")
im.resize((960, 600), Image.LANCZOS).quantize(colors=256, dither=Image.Dither.FLOYDSTEINBERG).save(sys.argv[2], optimize=True)
PYEOF
done
ls -l docs/images/organ-prepare.png docs/images/organ-liver.png docs/images/organ-kidney.png
