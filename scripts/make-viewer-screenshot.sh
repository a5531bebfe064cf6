#!/usr/bin/env bash
# Remakes docs/images/viewer.png, the README's screenshot: the headless viewer plays the prod-and-cut
# session examples/viewer-cut.json on the default model and writes its last frame; Pillow then
# shrinks it to 960 x 600 and a 256-colour palette (dithered) so the committed file stays small (about 100 kB).
# Runs under xvfb-run when there is no DISPLAY.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
VIEWER="$BUILD_DIR/bin/bemsurg-viewer"
[ -x "$VIEWER" ] || { echo "make-viewer-screenshot: build bemsurg_viewer first ($VIEWER missing)" >&2; exit 1; }
mkdir -p out docs/images
run=("$VIEWER" --script examples/viewer-cut.json --frames 75 --screenshot out/viewer-full.png)
if [ -z "${DISPLAY:-}" ]; then
  xvfb-run -a -s "-screen 0 1280x800x24" "${run[@]}"
else
  "${run[@]}"
fi
/usr/bin/python3 - <<'PYEOF'
from PIL import Image
im = Image.open("out/viewer-full.png").convert("RGB")
im.resize((960, 600), Image.LANCZOS).quantize(colors=256, dither=Image.Dither.FLOYDSTEINBERG).save(
    "docs/images/viewer.png", optimize=True)
PYEOF
ls -l docs/images/viewer.png
