#!/usr/bin/env bash
# Issue 26's acceptance run in CI (docs/haptics.md, "Feeling through a cut"): on the organ-like
# scene of examples/ (examples/scenes/liver.json, graded to about 1,800 elements) a sphere probe is
# held 3 mm deep while a 4-step cut runs 10 mm beside it (examples/liver-cut-session.json), in real
# time, twice: through `bemsurg session` and through the viewer's headless mode. Asserted:
#   * every cut step made (4), the delivered force never below 80 % of the model force and no
#     tick-to-tick change above 5 % per loop period (report.json / the viewer's "felt:" line);
#   * `bemsurg session`: the loop held >= 990 Hz on this machine (a low rate alone is measured once
#     more before it fails), the watchdog never acted.
# Run alone (CI runs it as a step of its own), since a rate is measured.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
OUT_DIR=${OUT_DIR:-out/check-cut-feel}
CLI="$BUILD_DIR/bin/bemsurg"
VIEWER="$BUILD_DIR/bin/bemsurg-viewer"
[ -x "$CLI" ] || { echo "check-cut-feel: $CLI was not built" >&2; exit 1; }
if [ -z "${DISPLAY:-}" ] && [ -z "${BEMSURG_CHECK_CUT_FEEL_INNER:-}" ]; then  # the viewer needs a display
  command -v xvfb-run >/dev/null || { echo "check-cut-feel: no DISPLAY and no xvfb-run (Debian package xvfb)" >&2; exit 1; }
  export BEMSURG_CHECK_CUT_FEEL_INNER=1
  exec xvfb-run -a -s "-screen 0 1280x800x24" bash "$0" "$@"
fi
rm -rf "$OUT_DIR"
mkdir -p "$OUT_DIR"
PY=/usr/bin/python3
[ -x "$PY" ] || PY=python3

# The session, checked by check_session (exit 0 ok, 1 a continuity failure, 3 only the rate was low).
check_session() {
"$PY" - "$1/report.json" <<'PYEOF'
import json, sys
j = json.load(open(sys.argv[1]))
checks = [
    ("elements in 1,000..2,000", 1000 <= j["elements"] <= 2000, j["elements"]),
    ("all 4 cut steps made", j["cuts"] == 4, j["cuts"]),
    ("delivered force >= 80 % of the model force", j["min_delivered_force_ratio"] >= 0.8, j["min_delivered_force_ratio"]),
    ("no tick-to-tick change above 5 %", j["max_tick_change_fraction"] <= 0.05, j["max_tick_change_fraction"]),
    ("the watchdog never acted", j["watchdog_ticks"] == 0, j["watchdog_ticks"]),
]
rate_ok = j["rate_hz"] >= 990.0
print(f"check-cut-feel: session: {j['elements']} elements, cut steps {j['cut_step_seconds']} s, "
      f"SCHED_FIFO priority {j['realtime_priority']}, {j['overruns']} overruns")
failed = False
for what, ok, value in checks + [("the loop held >= 990 Hz", rate_ok, j["rate_hz"])]:
    print(f"check-cut-feel: session: {'ok  ' if ok else 'FAIL'} {what}: {value}")
    failed |= not ok and what != "the loop held >= 990 Hz"
sys.exit(1 if failed else (0 if rate_ok else 3))
PYEOF
}
# The rate is a measurement on a shared machine (a VM's scheduling stalls come and go,
# docs/haptics.md "Measured"): a run whose only failure is a rate below 990 Hz is repeated once, and
# fails the check when the repeat is below it too. Continuity failures are not repeated.
"$CLI" session examples/scenes/liver.json --script examples/liver-cut-session.json -o "$OUT_DIR/session"
status=0
check_session "$OUT_DIR/session" || status=$?
if [ "$status" = 3 ]; then
  echo "check-cut-feel: session: the rate was below 990 Hz; repeating the session once"
  "$CLI" session examples/scenes/liver.json --script examples/liver-cut-session.json -o "$OUT_DIR/session-repeat"
  status=0
  check_session "$OUT_DIR/session-repeat" || status=$?
fi
[ "$status" = 0 ] || { echo "check-cut-feel: FAIL (session)" >&2; exit 1; }

if [ -x "$VIEWER" ]; then
  "$VIEWER" --script examples/liver-cut-session.json --frames 96 --size 960x600 --screenshot "$OUT_DIR/viewer.png" 2> "$OUT_DIR/viewer.log" ||
    { cat "$OUT_DIR/viewer.log" >&2; echo "check-cut-feel: FAIL: the viewer exited with an error" >&2; exit 1; }
  cat "$OUT_DIR/viewer.log"
  "$PY" - "$OUT_DIR/viewer.log" <<'PYEOF'
import re, sys
text = open(sys.argv[1]).read()
cuts = re.search(r"cuts: (\d+) steps accepted", text)
felt = re.search(r"felt: delivered force at least ([0-9.]+) % of the model's, largest tick-to-tick change ([0-9.]+) %", text)
fail = []
if not cuts or int(cuts.group(1)) != 4: fail.append("not all 4 cut steps were accepted")
if not felt: fail.append("no 'felt:' line")
else:
    if float(felt.group(1)) < 80.0: fail.append(f"the delivered force fell to {felt.group(1)} % of the model's")
    if float(felt.group(2)) > 5.0: fail.append(f"a tick changed the force by {felt.group(2)} %")
for f in fail: print("check-cut-feel: viewer: FAIL", f)
if not fail: print("check-cut-feel: viewer: ok (4 cut steps, force never below 80 %, no tick change above 5 %)")
sys.exit(1 if fail else 0)
PYEOF
else
  echo "check-cut-feel: $VIEWER was not built: the viewer part is skipped" >&2
  exit 1
fi
