#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.plot_format: a measure scene's plots at print size: one column wide
# (8.5 cm at 300 dpi: 1004 px, a 240.96 pt PDF page), also as PDF with render.plot_format, at
# the scene's render.size and dpi when given,
# each with its data in a CSV beside it (panel axes and units in the header),
# the same pixels from two identical runs (their bytes differ by the provenance comment, which
# holds the command line); a bad format is refused (exit 2, nothing run).
set -u
sablier=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "cli.plot_format: $*" >&2; exit 1; }
if "$sablier" --version | grep -q "render: not built"; then
  echo "cli.plot_format: rendering not built, skipped"
  exit 0
fi
for run in a b; do
  "$sablier" run "$scene" --out "$work/$run" --quiet --set 'render.plot_format="pdf"' \
    >"$work/$run.log" 2>&1 || fail "run $run: $(cat "$work/$run.log")"
done
plot=$work/a/stress_syy
[ -s "$plot.png" ] && [ -s "$plot.pdf" ] || fail "no stress_syy.png and .pdf: $(ls "$work/a")"
width=$(od -An -t u1 -j 16 -N 4 "$plot.png" | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')
[ "$width" = 1004 ] || fail "stress_syy.png is $width px wide, expected 1004 (8.5 cm at 300 dpi)"
# the plot's data beside it (docs/figures.md#plot-data): its axes with units, one row per point
[ -s "$plot.csv" ] || fail "no stress_syy.csv beside stress_syy.png"
sed -n 2p "$plot.csv" | grep -qF '# panel 1: x = \sigma_{yy} / (m g/d); y = y / d' ||
  fail "stress_syy.csv does not name the axes with units: $(sed -n 2p "$plot.csv")"
[ "$(sed -n 3p "$plot.csv")" = "panel,series,label,x,y,y_err" ] || fail "stress_syy.csv columns"
rows=$(grep -c '^1,1,' "$plot.csv")
[ "$rows" = 80 ] || fail "stress_syy.csv: $rows points, expected the profile's 80 bins"
grep -q '^# sablier plot data: stress_phi.png' "$work/a/stress_phi.csv" || fail "no stress_phi.csv"
grep -qx "stress_syy.csv" "$work/a/manifest.txt" || fail "the manifest misses stress_syy.csv"
grep -aq "MediaBox \[ 0 0 240.96 " "$plot.pdf" || fail "the PDF page is not 8.5 cm (240.96 pt) wide"
"$sablier" diff "$plot.png" "$work/b/stress_syy.png" --threshold 0 --shift 0 >"$work/diff.log" ||
  fail "two identical runs drew different plots: $(cat "$work/diff.log")"
# the scene's print keys size every plot: 12 cm at 150 dpi is 709 px
"$sablier" run "$scene" --out "$work/sized" --quiet --set 'render.size=[12.0, 9.0]' \
  --set 'render.dpi=150.0' >"$work/sized.log" 2>&1 || fail "sized run: $(cat "$work/sized.log")"
width=$(od -An -t u1 -j 16 -N 4 "$work/sized/stress_syy.png" |
  awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')
[ "$width" = 709 ] || fail "render.size = [12, 9] cm at 150 dpi: $width px wide, expected 709"
"$sablier" run "$scene" --out "$work/bad" --quiet --set 'render.plot_format="eps"' \
  >"$work/bad.log" 2>&1
rc=$?
[ "$rc" = 2 ] || fail "plot_format = eps: exit $rc, expected 2"
grep -q "unknown plot_format" "$work/bad.log" || fail "message: $(cat "$work/bad.log")"
[ ! -e "$work/bad" ] || [ -z "$(ls -A "$work/bad")" ] || fail "a refused scene wrote outputs"
echo "cli.plot_format: ok"
