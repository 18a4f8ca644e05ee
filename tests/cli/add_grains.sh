#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.add_grains: grains a stage adds (docs/scenes.md#grains-added-by-a-stage), from
# tests/cli/add_grains.scene. `check` prints their ids (after the scene's 100 grains: 100 for the
# projectile, 101 for the unnamed one); `trace` follows the projectile by name and a source's
# grain by id (105: the sources insert above the added grains); the projectile falls as
# x = x0 + vx t, y = y0 + vy t - g t^2 / 2 from the stage start (velocity Verlet is exact for a
# constant force, to rounding); 1 and 2 threads give the same bytes. Refused with exit 2 at the
# entry's file:line: an unknown key, an overlap with a wall or another added grain (at load), with
# the bed (as the stage starts), a name used twice, a traced name that no stage adds.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.add_grains: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$sablier" check "$scene" >"$work/check.log" 2>&1 || fail "check failed: $(cat "$work/check.log")"
grep -q "add grain 100 \`projectile\` at (1, 2.5), radius 0.06, species steel" "$work/check.log" ||
  fail "check prints no projectile id: $(cat "$work/check.log")"
grep -q "add grain 101 at (0.4, 2.6)" "$work/check.log" || fail "check: no id 101"
for n in 1 2; do
  "$sablier" run "$scene" --out "$work/t$n" --quiet --threads $n >"$work/t$n.log" 2>&1 ||
    fail "run --threads $n failed: $(cat "$work/t$n.log")"
done
for f in trace.csv bed.state drop.state walls.csv; do
  cmp -s "$work/t1/$f" "$work/t2/$f" || fail "$f differs between 1 and 2 threads"
done
python3 - "$work/t1/trace.csv" <<'PY' || fail "trace.csv: the projectile's path is off"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
p = [r for r in rows if r["id"] == "100"]
assert len(p) == 31, len(p)  # the drop stage: t = 0.5 to 0.8 every 0.01
assert len([r for r in rows if r["id"] == "105"]) == 82  # a source's grain, both stages (t = 0.5 in each)
g, t0 = 9.806, 0.5
for r in p:
    t = float(r["t"]) - t0
    x, y = 1.0 + 0.5 * t, 2.5 + 1.0 * t - 0.5 * g * t * t
    assert abs(float(r["x"]) - x) < 1e-8 and abs(float(r["y"]) - y) < 1e-8, (r, x, y)
    assert abs(float(r["vy"]) - (1.0 - g * t)) < 1e-8, r
assert float(p[-1]["y"]) < 2.4  # it fell
PY
# refused: SED-EXPRESSION, what stderr says, the line it names
refused() {
  local what=$1 expr=$2 pattern=$3 line=$4 command=${5:-check}
  sed "$expr" "$scene" >"$work/bad.scene"
  if [ "$command" = run ]; then
    "$sablier" run "$work/bad.scene" --out "$work/bad_out" --quiet >"$work/bad.log" 2>&1
  else
    "$sablier" check "$work/bad.scene" >"$work/bad.log" 2>&1
  fi
  local rc=$?
  [ "$rc" = 2 ] || fail "$what: exit $rc, expected 2: $(cat "$work/bad.log")"
  grep -q "bad.scene:$line: .*$pattern" "$work/bad.log" ||
    fail "$what: no 'bad.scene:$line: ...$pattern' in: $(cat "$work/bad.log")"
  rm -rf "$work/bad_out"
}
refused "unknown key" 's/radius = 0.06;/radius = 0.06; mass = 2.0;/' "unknown key .mass." 21
refused "wall overlap" 's/{ name = "bed"; time = { end = 0.5; }; }/{ name = "bed"; add = ( { x = 0.02; y = 2.0; radius = 0.03; } ); }/' \
  "overlaps wall 1" 19
refused "added grains overlap" 's/{ x = 0.4; y = 2.6; radius = 0.03; }/{ x = 1.05; y = 2.52; radius = 0.03; }/' \
  "overlaps the added grain 100" 23
refused "name twice" 's/{ x = 0.4; y = 2.6;/{ name = "projectile"; x = 0.4; y = 2.6;/' \
  "name .projectile. is used twice" 23
refused "unknown trace name" 's/trace = ( "projectile", 105 )/trace = ( "nothing" )/' \
  "no stage adds a grain named .nothing." 25
# into the bed: known only as the stage starts; the bed stage ran, the drop stage did not
refused "bed overlap" 's/y = 2.5; vx = 0.5;/y = 0.1; vx = 0.5;/' \
  "stage drop: added grain .projectile. (id 100) at (1, 0.1), radius 0.06, overlaps grain" 21 run
echo "cli.add_grains: ok"
