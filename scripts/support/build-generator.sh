# Sourced by the build scripts (run-tests.sh, run-sanitized-tests.sh): sets the array `generator` to
# -G Ninja for a new build tree when ninja is installed (setup-deps.sh installs ninja-build), else to
# nothing (CMake's default, make). Ninja runs the compiles of every target side by side, where make
# finishes a target's dependencies first and can leave a core idle while a library's last unit
# compiles. An existing tree keeps the generator it was made with. Usage: build_generator DIR.
build_generator() {
  generator=()
  if [ ! -f "$1/CMakeCache.txt" ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
}
