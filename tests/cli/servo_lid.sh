#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.servo_lid: a servo wall from a scene file (tests/cli/servo_lid.scene). `check` prints the
# servo's time scale; `run` writes walls.csv (a row per wall per energy row) and summary.json's
# steady mean, where the lid holds its 2000 N/m within 1 % and the base carries the grains'
# weight plus the lid's load.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.servo_lid: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$sablier" check "$scene" >"$work/check.log" 2>&1 || fail "check failed: $(cat "$work/check.log")"
grep -q "wall 3 servo .*time scale tau 0.00092" "$work/check.log" ||
  fail "check prints no servo time scale: $(cat "$work/check.log")"
"$sablier" run "$scene" --out "$work/run" --quiet >"$work/run.log" 2>&1 ||
  fail "run failed: $(cat "$work/run.log")"
head -1 "$work/run/walls.csv" | grep -q "^t,stage,wall,fx,fy,normal,tangential,torque,stress" ||
  fail "walls.csv header: $(head -1 "$work/run/walls.csv")"
rows=$(($(wc -l <"$work/run/walls.csv") - 1))
[ "$rows" = $((4 * 401)) ] || fail "walls.csv has $rows rows, expected 4 x 401"
python3 - "$work/run/summary.json" <<'PY' || fail "summary.json's wall means are off"
import json, sys
walls = json.load(open(sys.argv[1]))["walls"]
assert walls["window"] == [3, 4] and walls["samples"] == 101, walls
lid, base = walls["mean"][3], walls["mean"][0]
assert abs(lid["stress"] - 2000.0) < 20.0, lid
assert lid["offset"] > 0.5, lid
weight = 150 * 1000.0 * 3.141592653589793 * 0.05 ** 2 * 9.806  # about: radii +- 8 %
assert abs(-base["fy"] - (weight + 2 * lid["stress"])) < 0.05 * weight, (base, weight)
PY
echo "cli.servo_lid: ok"
