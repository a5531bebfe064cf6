#!/usr/bin/env bash
# Installs bemsurg's build and test dependencies from Debian's archive (Debian 12 / Ubuntu 22.04+).
# Idempotent: packages already present are skipped, so re-running costs a dpkg query.
# Uses sudo only when not root. Nothing is downloaded from anywhere but the distribution's archive.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev catch2 libsuitesparse-dev libopenblas-dev liblapacke-dev nlohmann-json3-dev
  libglfw3-dev libimgui-dev libstb-dev libgl-dev libegl-dev xvfb xauth
  gnuplot-nox python3-matplotlib python3-pil python3-numpy
  libgmsh-dev   # the graded remesher (src/mesh/graded_remesher.cpp, optional: docs/graded.md)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup-deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "setup-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
