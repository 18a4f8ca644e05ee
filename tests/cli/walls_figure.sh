#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.walls_figure: output.walls draws walls.png, each wall's normal stress against time (and with
# render.plot_format = "pdf" walls.pdf beside it), from tests/cli/servo_lid.scene run short. The
# PDF passes the figure lint (tests/lint/figure_lint.py: every axis labelled with its unit), its
# axes read "t (s)" and "σn (N/m)", and walls.csv stays the measure's own file (the plot's data
# is not written over it).
set -u
sablier=$1 scene=$2 lint=$3 work=$4
fail() { echo "cli.walls_figure: $*" >&2; exit 1; }
if "$sablier" --version | grep -q "render: not built"; then
  echo "cli.walls_figure: rendering not built, skipped"
  exit 0
fi
rm -rf "$work"
mkdir -p "$work"
"$sablier" run "$scene" --out "$work/run" --quiet --set stages.press.time.end=1 \
  --set 'render.plot_format="pdf"' >"$work/run.log" 2>&1 || fail "run failed: $(cat "$work/run.log")"
for f in walls.png walls.pdf; do
  [ -s "$work/run/$f" ] || fail "no $f: $(ls "$work/run")"
  grep -qx "$f" "$work/run/manifest.txt" || fail "$f not in manifest.txt"
done
head -1 "$work/run/walls.csv" | grep -q "^t,stage,wall,fx,fy,normal" ||
  fail "walls.csv was overwritten: $(head -1 "$work/run/walls.csv")"
python3 "$lint" "$work/run/walls.pdf" || fail "the figure lint complains about walls.pdf"
if command -v pdftotext >/dev/null; then
  text=$(pdftotext "$work/run/walls.pdf" -)
  grep -q "^t (s)$" <<<"$text" || fail "no time axis label in: $text"
  grep -q "(N/m)$" <<<"$text" || fail "no stress axis label in: $text"
  grep -q "wall 3" <<<"$text" || fail "no legend entry of wall 3 in: $text"
fi
echo "cli.walls_figure: ok"
