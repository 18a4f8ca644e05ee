#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.settle_window (docs/scenes.md, stages: settle): the grain of
# tests/cli/settle_window.scene bounces for ever; its kinetic energy is below 0.05 J within
# 14 ms of each apex. The one-row test (no `hold`) stops the stage at the first apex (about
# 0.51 s); with `hold = 0.05` (longer than the 29 ms near an apex) it runs to its end unsettled;
# with `kinetic_per_grain_below` (one mobile grain: the same level) and `hold = 0.02` it settles
# 20 ms after the one-row test did.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.settle_window: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# run NAME [--set ...]: "settled end_time" of stage fall from summary.json
run() {
  local name=$1
  shift
  "$sablier" run "$scene" --out "$work/$name" --quiet "$@" >"$work/$name.log" 2>&1 ||
    fail "$name: run failed: $(cat "$work/$name.log")"
  python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))["stages"][0]
print(str(s["settled"]).lower(), "%.3f" % s["end_time"])' "$work/$name/summary.json"
}
one=$(run one)
case "$one" in "true 0.5"*) ;; *) fail "one row: settled, end = $one, expected true 0.5.." ;; esac
window=$(run window --set stages.fall.settle.hold=0.05)
[ "$window" = "false 1.000" ] || fail "hold 0.05: settled, end = $window, expected false 1.000"
per=$(run per --unset stages.fall.settle.kinetic_below \
  --set stages.fall.settle.kinetic_per_grain_below=0.05 --set stages.fall.settle.hold=0.02)
t1=${one#true } t2=${per#true }
[ "${per%% *}" = true ] && python3 -c "import sys; sys.exit(abs($t2 - $t1 - 0.02) > 0.0015)" ||
  fail "per grain, hold 0.02: settled, end = $per, expected true at $t1 + 0.02"
"$sablier" check "$scene" --set stages.fall.settle.kinetic_per_grain_below=1 >"$work/both.log" 2>&1
[ $? = 2 ] && grep -q "settle_window.scene:[0-9]*: .*give one of \`kinetic_below\`" "$work/both.log" ||
  fail "both levels: $(cat "$work/both.log")"
echo "cli.settle_window: ok"
