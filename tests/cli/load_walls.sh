#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.load_walls: a stage that loads a checkpoint keeps the checkpoint's walls, so a checkpoint
# whose walls are not the scene's (another motion, another position, another count) is refused
# at load (`check` and `run`: file:line, exit 2, nothing written), where its walls were silently
# used and the scene's wall motions ignored; the same walls are accepted.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.load_walls: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$sablier" run "$scene" --out "$work/bed" --quiet >"$work/bed.log" 2>&1 ||
  fail "bed run failed: $(cat "$work/bed.log")"
state=$work/bed/rest.state
[ -s "$state" ] || fail "no $state"
load="stages.rest.load=\"$state\""
"$sablier" check "$scene" --set "$load" >"$work/same.log" 2>&1 ||
  fail "the same walls refused: $(cat "$work/same.log")"
"$sablier" run "$scene" --out "$work/same" --quiet --set "$load" >"$work/same.log" 2>&1 ||
  fail "run with the same walls failed: $(cat "$work/same.log")"
refused() { # refused NAME PATTERN SCENE --set ...: check and run exit 2 with PATTERN, run writes nothing
  local name=$1 pattern=$2 scene=$3
  shift 3
  "$sablier" check "$scene" --set "$load" "$@" >"$work/$name.log" 2>&1
  local rc=$?
  [ "$rc" = 2 ] || fail "$name: check exit $rc, expected 2: $(cat "$work/$name.log")"
  grep -q "stages.rest.load: checkpoint .*$pattern" "$work/$name.log" ||
    fail "$name: message: $(cat "$work/$name.log")"
  "$sablier" run "$scene" --out "$work/$name" --quiet --set "$load" "$@" >"$work/$name.log" 2>&1
  rc=$?
  [ "$rc" = 2 ] || fail "$name: run exit $rc, expected 2"
  [ ! -e "$work/$name" ] || fail "$name: run wrote $work/$name"
}
refused motion "wall 0 differs from the scene's in motion" "$scene" --set 'walls.0.motion="shake"'
refused position "wall 0 differs from the scene's in position or shape" "$scene" \
  --set 'walls.0.to=[1.0, 0.01]'
sed 's/^walls = (.*/walls = ( { from = [-1.0, 0.0]; to = [1.0, 0.0]; }, { from = [-1.0, 0.0]; to = [-1.0, 1.0]; } );/' \
  "$scene" >"$work/two_walls.scene"
refused count "has 1 walls, the scene 2" "$work/two_walls.scene"
echo "cli.load_walls: ok"
