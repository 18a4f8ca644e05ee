#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.late_checks: what a later stage needs is checked at load, by `check` and before
# `run` or a driver writes anything:
#   species    a stage `load` state whose grain has a species the scene lacks: was accepted by
#              check and failed in run after energy.csv and summary.json were written
#   cell_size  a state whose exact-resume section has a cell size of 0: the grid set-up looped
#              for ever; now refused with the file
#   bne_period --set bne.period=1e300 (an infinite shaking amplitude): passed check and failed
#              after the settle stage ran; `sablier bne` left samples.csv, rise.csv, ldf.csv
set -u
sablier=$1 base=$2 bne=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.late_checks: $*" >&2; exit 1; }
# refused SCENE_ARGS... : check and run exit 2 with $want on stderr, run leaves no folder
refused() {
  "$sablier" check "$@" >/dev/null 2>"$work/err.txt"
  rc=$?
  [ "$rc" = 2 ] || fail "check $*: exit $rc, expected 2: $(cat "$work/err.txt")"
  grep -q -- "$want" "$work/err.txt" || fail "check $*: no '$want' in: $(cat "$work/err.txt")"
  "$sablier" run "$@" --out "$work/out" --quiet 2>"$work/err.txt"
  rc=$?
  [ "$rc" = 2 ] || fail "run $*: exit $rc, expected 2: $(cat "$work/err.txt")"
  [ ! -e "$work/out" ] || fail "run $* left $(ls "$work/out")"
}
# a scene whose only stage starts from $1 (in $work)
load_scene() {
  sed '/^time = {/,/^};/d' "$base" >"$work/load.scene"
  printf 'time = { dt = 1e-5; end = 0.01; };\nstages = ( { name = "go"; load = "%s"; } );\n' \
    "$1" >>"$work/load.scene"
}

# species: a state of a two-species scene (the falling grain species 1) loaded by the base scene
sed -e 's/^\(  { name = "grain";.*}\)$/\1,\n  { name = "other"; density = 1190.0; k_n = 5e5; gamma_n = 0.0; }/' \
  -e 's/{ x = 0.0; y = 1.025; r = 0.1; }/{ x = 0.0; y = 1.025; r = 0.1; species = 1; }/' \
  "$base" >"$work/two.scene"
"$sablier" run "$work/two.scene" --out "$work/two" --quiet --set time.end=0.01 2>"$work/err.txt" ||
  fail "the two-species run failed: $(cat "$work/err.txt")"
cp "$work/two/run.state" "$work/species.state"
load_scene species.state
want="species.state\`: grain 0 has species 1; the scene has species 0 to 0"
refused "$work/load.scene"

# cell_size: the base scene's own state with the continuation section's cell size set to 0
"$sablier" run "$base" --out "$work/one" --quiet --set time.end=0.01 2>"$work/err.txt" ||
  fail "the base run failed: $(cat "$work/err.txt")"
cp "$work/one/run.state" "$work/cell.state"
at=$(grep -obUa "EXACT-1" "$work/cell.state" | head -1 | cut -d: -f1)
[ -n "$at" ] || fail "no continuation section in the base run's state"
# the header: tag[8], then dt, start_time, def_skin, skin, skin_min, skin_max, skin_density,
# disp_limit2, max_radius, cell_size (docs/state-format.md)
head -c 8 /dev/zero | dd of="$work/cell.state" bs=1 seek=$((at + 80)) conv=notrunc 2>/dev/null
load_scene cell.state
want="cell.state: continuation section: a cell size not finite and > 0"
refused "$work/load.scene"

# bne_period: check and run refuse it at the `period` line; `sablier bne` writes nothing
want="period 1e+300 s and Gamma [^ ]* give a shaking amplitude inf"
refused "$bne" --set bne.period=1e300
"$sablier" bne "$bne" --seeds 2 --jobs 1 --quiet --set bne.period=1e300 --out "$work/bne" \
  2>"$work/err.txt"
rc=$?
[ "$rc" = 2 ] || fail "bne: exit $rc, expected 2: $(cat "$work/err.txt")"
[ ! -e "$work/bne" ] || fail "bne left $(ls -R "$work/bne")"
echo "cli.late_checks: ok"
