#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.sweep_vary_units, cli.sweep_vary_time_units: `sablier sweep SCENE --vary KEY=VALUES` without
# a sweep file labels crater_height's x axis with the key and its unit from the scene keys' tables
# (scene_key_quantity, docs/cli.md#sablier-sweep): LABEL ("species.0.mu (1)", "time.dt (s)") in
# the plot's data CSV and, where rendering and pdftotext are there, in the PDF, which passes the
# figure lint (tests/lint/figure_lint.py), with no warning; a key whose unit is not recorded
# (guard.every) is named bare, with a warning. The scene is cut short with --set as
# tests/lint/figure_scenes.sh does.
#   sweep_vary_units.sh SABLIER SCENE WORK LINT KEY=VALUES LABEL
set -u
sablier=$1 scene=$2 work=$3 lint=$4 vary=$5 label=$6
name=$(basename "$work")
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.$name: $*" >&2; exit 1; }
cut=(--set grains.rain.max_count=80 --set stages.deposit.time.end=0.2
  --set stages.deposit.settle.after=0.1 --set stages.collapse.time.end=0.1
  --set stages.collapse.settle.after=0.05)

"$sablier" sweep "$scene" --vary "$vary" --out "$work/key" --quiet \
  --set 'render.plot_format="pdf"' "${cut[@]}" >"$work/key.log" 2>&1 ||
  fail "sweep --vary $vary: $(cat "$work/key.log")"
if "$sablier" --version | grep -q "render: not built"; then
  echo "cli.$name: rendering not built, the figures skipped"
else
  data=$work/key/crater_height.csv
  [ -s "$data" ] || fail "no crater_height.csv: $(ls "$work/key")"
  sed -n 2p "$data" | grep -qF "# panel 1: x = $label; y = " ||
    fail "crater_height.csv does not name the x axis $label: $(sed -n 2p "$data")"
  if command -v pdftotext >/dev/null; then
    pdftotext "$work/key/crater_height.pdf" - | grep -qF "$label" ||
      fail "crater_height.pdf: no x label '$label'"
    python3 "$lint" "$work/key"/*.pdf || fail "the figure lint complains on the sweep's plots"
  fi
fi

# a key with no recorded unit: named bare, and said so (nothing runs with --dry-run)
"$sablier" sweep "$scene" --vary guard.every=1,2 --out "$work/every" --dry-run \
  >"$work/every.out" 2>"$work/every.err" ||
  fail "sweep --vary guard.every --dry-run: $(cat "$work/every.err")"
grep -qF 'warning: no unit is recorded for `guard.every`' "$work/every.err" ||
  fail "no warning for guard.every: $(cat "$work/every.err")"
grep -q warning "$work/key.log" && fail "a warning for $vary: $(cat "$work/key.log")"
echo "cli.$name: the x axis names $label"
