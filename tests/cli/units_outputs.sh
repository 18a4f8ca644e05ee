#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# units_outputs.sh SABLIER WORK KIND: the shipped scenes written in d = g = 1 (scenes/measure/column.scene,
# scenes/chute/chute.scene, units = "normalised") name their own units in every output kind, never
# SI (docs/scenes.md#units):
#   summary.json  "simulated_time" (not "simulated_seconds") and a "units" member naming d,
#                 sqrt(d/g), m g, m g d, m g/d;
#   CSV headers   no SI-suffixed column (x_m, t_s, e_J, f_N); the plot data's header lines name
#                 d and m g/d (or sqrt(g d)), never m, s, N;
#   figures       the time stamp in sqrt(d/g) and the colour bar's unit (contact force in m g,
#                 speed in sqrt(g d)), read from PDF output by pdftotext: a run's figure and
#                 `sablier render` of its checkpoint (a movie frame is drawn with the same style);
#                 and an SI scene with units = "reduced" (tests/cli/reproducible.scene): force
#                 and speed colour bars in m g and sqrt(g d), never N or m/s.
# KIND (summary, csv, figures) chooses which of the three kinds is checked.
set -u
sablier=$1
work=$2
kind=$3
rm -rf "$work"
mkdir -p "$work"
fails=0
fail() { echo "units_outputs: $*" >&2; fails=$((fails + 1)); }
have() { grep -qF -- "$2" "$1" || fail "$1 lacks '$2'"; }
lacks() { if grep -qE -- "$2" "$1"; then fail "$1 has '$(grep -oE -- "$2" "$1" | head -1)'"; fi; }

"$sablier" run scenes/measure/column.scene --out "$work/column" --quiet \
  --set grains.rain.max_count=60 --set stages.rain.time.end=1.5 --set stages.rest.time.end=1 \
  --set stages.rest.measures.0.window=0.5 || { echo "units_outputs: column run failed" >&2; exit 1; }
"$sablier" run scenes/chute/chute.scene --out "$work/chute" --quiet \
  --set stages.settle.time.end=1.5 --set stages.flow.time.end=1 \
  --set stages.flow.measures.0.window=0.5 --set 'output.movie=[]' \
  --set 'output.figures.0.format="pdf"' --set output.figures.0.time_stamp=true \
  --set output.figures.0.colorbar=true || { echo "units_outputs: chute run failed" >&2; exit 1; }

if [ "$kind" = summary ]; then
for run in column chute; do
  s=$work/$run/summary.json
  have "$s" '"simulated_time": '
  lacks "$s" '"simulated_seconds"'
  have "$s" '"units": {"system": "normalised", "length": "d", "time": "sqrt(d/g)", "mass": "m", "speed": "sqrt(g d)", "force": "m g", "energy": "m g d", "stress": "m g/d"}'
done
fi

if [ "$kind" = csv ]; then
for csv in column/energy.csv column/stress.csv column/field.csv column/fall.csv chute/energy.csv \
           chute/velocity.csv; do
  head -1 "$work/$csv" >"$work/header.txt"
  lacks "$work/header.txt" '_(m|s|N|J|kg)(,|$)|\((m|s|N|J|kg|m/s)\)'
done
have "$work/column/stress_syy.csv" '# panel 1: x = \sigma_{yy} / (m g/d); y = y / d'
have "$work/chute/velocity_vx.csv" 'y = y / d'
have "$work/chute/velocity_vx.csv" "$(printf 'x = v_x / \xe2\x88\x9a(gd)')"
for csv in column/stress_syy.csv column/stress_phi.csv chute/velocity_vx.csv; do
  grep '^#' "$work/$csv" >"$work/header.txt"
  lacks "$work/header.txt" '\((m|s|N|N/m|m/s)\)|/ (m|s|N)(;|$)'
done
fi

if [ "$kind" = figures ]; then
root=$(printf '\xe2\x88\x9a')
pdftotext "$work/chute/chute.pdf" "$work/chute.txt" || fail "pdftotext chute.pdf"
have "$work/chute.txt" "speed (${root}(gd))"
grep -qE "^t = [0-9.]+ ${root}\(d/g\)$" "$work/chute.txt" || fail "chute.pdf: no time stamp in sqrt(d/g)"
for by in force speed height; do # height: bands, no colour bar
  "$sablier" render "$work/column/rest.state" --scene scenes/measure/column.scene \
    --color-by $by --colorbar --time-stamp --scale-bar -o "$work/column_$by.pdf" ||
    { fail "render --color-by $by"; continue; }
  pdftotext "$work/column_$by.pdf" "$work/column_$by.txt" || fail "pdftotext column_$by.pdf"
  grep -qE "^t = [0-9.]+ ${root}\(d/g\)$" "$work/column_$by.txt" ||
    fail "column_$by.pdf: no time stamp in sqrt(d/g)"
  lacks "$work/column_$by.txt" '\((N|m/s|m|s)\)| s$|\(d = '
done
have "$work/column_force.txt" "contact force (m g)"
have "$work/column_speed.txt" "speed (${root}(gd))"
# units = "reduced" on an SI scene: force and speed colour bars in m g and sqrt(g d), from a run's
# figure (the run's scales) and from `sablier render` of its state (that state's grains)
for by in force speed; do
  "$sablier" run tests/cli/reproducible.scene --out "$work/reduced_$by" --quiet \
    --set 'units="reduced"' --set "render.color_by=\"$by\"" || { fail "reduced run ($by)"; continue; }
  pdftotext "$work/reduced_$by/drop.pdf" "$work/reduced_$by.txt" || fail "pdftotext reduced $by"
  state=$(ls "$work/reduced_$by"/*.state | head -1)
  "$sablier" render "$state" --scene tests/cli/reproducible.scene --set 'units="reduced"' \
    --color-by $by --colorbar -o "$work/reduced_render_$by.pdf" || fail "reduced render ($by)"
  pdftotext "$work/reduced_render_$by.pdf" "$work/reduced_render_$by.txt" ||
    fail "pdftotext reduced render $by"
  for txt in "$work/reduced_$by.txt" "$work/reduced_render_$by.txt"; do
    lacks "$txt" '\((N|m/s)\)'
  done
done
for txt in "$work/reduced_force.txt" "$work/reduced_render_force.txt"; do
  have "$txt" "contact force (m g)"
done
for txt in "$work/reduced_speed.txt" "$work/reduced_render_speed.txt"; do
  have "$txt" "speed (${root}(gd))"
done
fi

if [ $fails -gt 0 ]; then
  echo "units_outputs: $fails failures" >&2
  exit 1
fi
echo "units_outputs: $kind in the scenes' own units (d, sqrt(d/g), m g), never SI"
