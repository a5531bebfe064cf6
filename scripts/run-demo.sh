#!/usr/bin/env bash
# Installs the dependencies, builds bemsurg and runs the main demo: a soft-tissue block sagging
# under its own weight and then prodded by a flat tool. Results land in out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DBEMSURG_BUILD_TESTS=OFF -DBEMSURG_BUILD_BENCHMARKS=OFF
cmake --build "$BUILD_DIR" -j"${JOBS:-2}" --target bemsurg_cli
BEMSURG="$BUILD_DIR/bin/bemsurg"
mkdir -p out/demo
"$BEMSURG" solve examples/scenes/cube_under_gravity.json -o out/demo/solve
echo "demo: self-weight solution written to out/demo/solve (elements.csv, surface.vtk, report.json)"
"$BEMSURG" press examples/scenes/cube_under_gravity.json --tool flat:0.02 --at 0,0,0.08 --direction 0,0,-1 \
  --depth 0.002 -o out/demo/press
echo "demo: flat-punch press written to out/demo/press (elements.csv, force.json)"
cat out/demo/press/force.json
