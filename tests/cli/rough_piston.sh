#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.rough_piston: a rough piston (a group of fixed grains moving as one rigid body,
# tests/cli/rough_piston.scene). Free, it falls onto the bed and rests there: the grains' force
# on it balances its weight m g within 1 % over the window. With a servo (--servo, tests/cli/rough_piston_servo.scene) it
# holds its target stress within 1 %. walls.csv and summary.json report it after the walls, as wall 3.
set -u
sablier=$1 scene=$2 work=$3
shift 3
fail() { echo "cli.rough_piston: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
mode=free
if [ "${1:-}" = "--servo" ]; then
  mode=servo
  shift
fi
"$sablier" run "$scene" --out "$work/run" --quiet "$@" >"$work/run.log" 2>&1 ||
  fail "run failed: $(cat "$work/run.log")"
rows=$(($(wc -l <"$work/run/walls.csv") - 1))
[ "$rows" = $((4 * 6001)) ] || fail "walls.csv has $rows rows, expected 4 x 6001"
python3 - "$work/run/summary.json" "$mode" <<'PY' || fail "summary.json's piston mean is off"
import json, sys
walls = json.load(open(sys.argv[1]))["walls"]
piston = walls["mean"][3]
assert piston["offset"] > 0.05, piston
if sys.argv[2] == "free":
    weight = 20.0 * 9.806
    assert abs(piston["normal"] - weight) < 0.01 * weight, (piston, weight)
else:
    assert abs(piston["stress"] - 2000.0) < 20.0, piston
PY
echo "cli.rough_piston ($mode): ok"
