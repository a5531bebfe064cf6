#!/usr/bin/env bash
# Installs bemsurg's build and test dependencies from Debian's archive (Debian 12 / Ubuntu 22.04+).
# Idempotent: packages already present are skipped, so re-running costs a dpkg query.
# Uses sudo only when not root. Nothing is downloaded from anywhere but the distribution's archive.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build  # ninja: README's test command builds with it (scripts/run-tests.sh)
  libeigen3-dev catch2 libsuitesparse-dev libopenblas-dev liblapacke-dev nlohmann-json3-dev
  libglfw3-dev libimgui-dev libstb-dev libgl-dev libegl-dev xvfb xauth
  gnuplot-nox python3-matplotlib python3-pil python3-numpy
  libgmsh-dev   # the graded remesher (src/meshing/graded_remesher.cpp, optional: docs/graded.md)
  libcgal-dev   # mesh repair for `bemsurg prepare` (src/meshing/cgal_repair.cpp, optional: docs/organs.md)
  libhmat-oss-dev  # the hierarchical-matrix backend (src/elastostatics/hierarchical_solver.cpp, optional: docs/solvers.md; GPL-2.0-or-later)
  libopenmpi-dev openmpi-bin libscalapack-openmpi-dev  # tables across MPI ranks and the scalapack solve (src/distributed/, optional: docs/distributed.md)
  locales       # de_DE.UTF-8 for the comma-decimal locale test (tests/test_locale.cpp)
  doxygen       # the API reference (target bemsurg_api_docs, docs/api/)
  clang-format  # the format check (scripts/check-structure.sh, .clang-format)
  calculix-ccx python3-gmsh python3-scipy  # the report's finite-element peer (scripts/run-benchmarks.sh, docs/report.md; scipy: calculix_peer.py's rim distances and crease split)
)

# A comma-decimal locale, so tests/test_locale.cpp runs rather than reporting itself skipped.
# localedef writes it into /usr/lib/locale without touching /etc/locale.gen.
ensure_locale() {
  locale -a 2>/dev/null | grep -qi '^de_DE\.utf-\?8$' && return 0
  command -v localedef >/dev/null || { echo "setup-deps: no localedef; test_locale will be skipped" >&2; return 0; }
  echo "setup-deps: generating the de_DE.UTF-8 locale"
  $SUDO localedef -i de_DE -f UTF-8 de_DE.UTF-8 || echo "setup-deps: could not generate de_DE.UTF-8; test_locale will be skipped" >&2
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

SUDO=""
if [ "$(id -u)" -ne 0 ] && command -v sudo >/dev/null; then SUDO="sudo"; fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#packages[@]} packages already installed"
  ensure_locale
  exit 0
fi

if [ "$(id -u)" -ne 0 ] && [ -z "$SUDO" ]; then
  echo "setup-deps: not root and no sudo; install: ${missing[*]}" >&2
  exit 1
fi
echo "setup-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
ensure_locale
