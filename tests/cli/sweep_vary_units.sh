#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.sweep_vary_units: `sablier sweep SCENE --vary KEY=...` without a sweep file labels
# crater_height's x axis with the key and its unit from the species table (scene_key_quantity,
# docs/cli.md#sablier-sweep): "species.0.mu (1)" in the plot's data CSV and, where rendering and
# pdftotext are there, in the PDF, which passes the figure lint (tests/lint/figure_lint.py); a key
# whose unit is not recorded is named bare, with a warning. The scene is cut short with --set as
# tests/lint/figure_scenes.sh does.
set -u
sablier=$1 scene=$2 work=$3 lint=$4
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.sweep_vary_units: $*" >&2; exit 1; }
cut=(--set grains.rain.max_count=80 --set stages.deposit.time.end=0.2
  --set stages.deposit.settle.after=0.1 --set stages.collapse.time.end=0.1
  --set stages.collapse.settle.after=0.05)

"$sablier" sweep "$scene" --vary species.0.mu=0.1,0.5 --out "$work/mu" --quiet \
  --set 'render.plot_format="pdf"' "${cut[@]}" >"$work/mu.log" 2>&1 ||
  fail "sweep --vary species.0.mu: $(cat "$work/mu.log")"
if "$sablier" --version | grep -q "render: not built"; then
  echo "cli.sweep_vary_units: rendering not built, the figures skipped"
else
  data=$work/mu/crater_height.csv
  [ -s "$data" ] || fail "no crater_height.csv: $(ls "$work/mu")"
  sed -n 2p "$data" | grep -qF '# panel 1: x = species.0.mu (1); y = ' ||
    fail "crater_height.csv does not name the x axis with its unit: $(sed -n 2p "$data")"
  if command -v pdftotext >/dev/null; then
    pdftotext "$work/mu/crater_height.pdf" - | grep -qF 'species.0.mu (1)' ||
      fail "crater_height.pdf: no x label 'species.0.mu (1)'"
    python3 "$lint" "$work/mu"/*.pdf || fail "the figure lint complains on the sweep's plots"
  fi
fi

# a key with no recorded unit: named bare, and said so (nothing runs with --dry-run)
"$sablier" sweep "$scene" --vary time.dt=5e-5,4e-5 --out "$work/dt" --dry-run \
  >"$work/dt.out" 2>"$work/dt.err" || fail "sweep --vary time.dt --dry-run: $(cat "$work/dt.err")"
grep -qF 'warning: no unit is recorded for `time.dt`' "$work/dt.err" ||
  fail "no warning for time.dt: $(cat "$work/dt.err")"
grep -q warning "$work/mu.log" && fail "a warning for species.0.mu: $(cat "$work/mu.log")"
echo "cli.sweep_vary_units: the x axis names species.0.mu (1)"
