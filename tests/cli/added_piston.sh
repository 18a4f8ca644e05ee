#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.added_piston: a rough piston built by a stage (tests/cli/added_piston.scene): the bed is
# deposited first, then stage "press" adds a row of grains of group "piston", whose body (dormant
# until then) holds 2000 N/m by its servo within 1 % over the window of walls.csv's means.
# trace.csv names two of the added grains by their ids (270 and 289: after the 270 of the
# scene's rain), which move down together, rigidly. The run on 1, 2, 3 and 8 threads writes the
# same bytes (walls.csv, trace.csv, energy.csv, each stage's .state).
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.added_piston: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
for t in 1 2 3 8; do
  "$sablier" run "$scene" --out "$work/run$t" --quiet --threads $t >"$work/run$t.log" 2>&1 ||
    fail "run on $t threads failed: $(cat "$work/run$t.log")"
done
python3 - "$work/run1" <<'PY' || fail "the added piston's stress or its traced grains are off"
import csv, json, sys
run = sys.argv[1]
piston = json.load(open(run + "/summary.json"))["walls"]["mean"][3]
assert piston["offset"] > 0.05, piston
assert abs(piston["stress"] - 2000.0) < 20.0, piston
rows = list(csv.DictReader(open(run + "/trace.csv")))
ids = {r["id"] for r in rows}
assert ids == {"270", "289"}, ids
first = min(float(r["t"]) for r in rows)
assert first >= 0.8 - 1e-9, first  # the grains exist from the stage that adds them
last = {r["id"]: r for r in rows if float(r["t"]) == max(float(q["t"]) for q in rows)}
left, right = last["270"], last["289"]
assert float(left["x"]) == 0.05 and abs(float(right["x"]) - 1.95) < 1e-12, (left, right)
assert float(left["y"]) < 1.0 and float(left["y"]) == float(right["y"]), (left, right)
print("added piston: stress %.6g N/m, offset %.4g m, traced y %s" %
      (piston["stress"], piston["offset"], left["y"]))
PY
for t in 2 3 8; do
  for f in walls.csv trace.csv energy.csv deposit.state press.state; do
    cmp -s "$work/run1/$f" "$work/run$t/$f" || fail "$f on $t threads differs from 1 thread"
  done
done
echo "cli.added_piston: ok"
