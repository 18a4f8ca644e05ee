#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.servo_flip: the 1.98 m lid of tests/cli/servo_flip.scene (force servo, 4000 N, gain 1e-3,
# gamma_n 200 over 150 frictionless grains; docs/scenes.md "Damping bound").
#   implicit (the default): the lid's mean load over the window is within 1 % of the target,
#     sampled every 10 steps and every 2 steps alike (the two means within 1 % of each other),
#     no flip counted, no warning;
#   explicit: its speed flips between +-max_speed every step, which the run tells on stderr
#     (wall 3, the time) and counts in summary.json's walls mean (servo_flips > 0).
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.servo_flip: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
run() { # name, then --set options
  local name=$1
  shift
  "$sablier" run "$scene" --out "$work/$name" --quiet "$@" >"$work/$name.log" 2>&1 ||
    fail "run $name failed: $(cat "$work/$name.log")"
}
run every10
run every2 --set output.energy_every=0.0002
run explicit --set 'walls.3.servo.damping="explicit"'
python3 - "$work" <<'PY' || fail "the lid's means or flip counts are off"
import json, sys
work = sys.argv[1]
def lid(name):
    return json.load(open("%s/%s/summary.json" % (work, name)))["walls"]["mean"][3]
a, b = lid("every10"), lid("every2")
print("implicit: every 10 steps %.6g N, every 2 steps %.6g N, flips %d %d"
      % (a["normal"], b["normal"], a["servo_flips"], b["servo_flips"]))
for m in (a, b):
    assert abs(m["normal"] - 4000.0) < 40.0, m
    assert m["servo_flips"] == 0, m
assert abs(a["normal"] - b["normal"]) < 0.01 * 4000.0, (a, b)
e = lid("explicit")
print("explicit: every 10 steps %.6g N, flips %d" % (e["normal"], e["servo_flips"]))
assert e["servo_flips"] > 0, e
PY
for name in every10 every2; do
  ! grep -q "servo flips" "$work/$name.log" || fail "$name warns: $(cat "$work/$name.log")"
done
grep -q "warning: wall 3's servo flips its speed between +max_speed and -max_speed every step since t = [0-9.e-]* s (stage press" \
  "$work/explicit.log" || fail "the explicit run does not tell its flips: $(cat "$work/explicit.log")"
[ "$(grep -c "servo flips" "$work/explicit.log")" = 1 ] ||
  fail "the flips are told more than once: $(cat "$work/explicit.log")"
echo "cli.servo_flip: ok"
