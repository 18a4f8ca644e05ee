#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/publication_figures.sh: redraws the "after" figures of docs/figures.md (before and
# after) with today's renderer at single-column print size (8.5 cm wide, 300 dpi, 8 pt text)
# into OUT (default docs/figures/publication/): bne_phase_field_after.png, crater_collapse_after.png
# and crater_field_after.png. The "before" figures are the older renderer's and stay as they are.
#
#   scripts/publication_figures.sh [--sablier PATH] [OUT]
#
# The runs go to OUT/.runs/ and are removed at the end. Exit status: 0, or that of a failing run.
set -euo pipefail

sablier=""
out=""
while [ $# -gt 0 ]; do
  case "$1" in
  --sablier) sablier=${2:?--sablier needs a path}; shift ;;
  -h | --help) sed -n '3,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  -*) echo "publication_figures.sh: unknown option $1" >&2; exit 2 ;;
  *) out=$1 ;;
  esac
  shift
done
[ -z "$sablier" ] || sablier=$(realpath "$sablier")
[ -z "$out" ] || out=$(realpath -m "$out")
cd "$(dirname "$0")/.." # the scenes' paths are relative to the repository root
[ -n "$sablier" ] || sablier=$PWD/build/sablier
[ -n "$out" ] || out=$PWD/docs/figures/publication
[ -x "$sablier" ] || { echo "publication_figures.sh: no sablier at $sablier (build it first)" >&2; exit 2; }
runs=$out/.runs
rm -rf "$runs"
mkdir -p "$runs"

# take FILE NAME: FILE becomes OUT/NAME through a temporary name
take() {
  cp "$1" "$out/$2.tmp" && mv "$out/$2.tmp" "$out/$2"
}

# the Brazil-nut box-frame phase field (reduced units): a tall box, so 8.5 x 12 cm
"$sablier" run scenes/brazil_nut/small.scene --out "$runs/bne" --quiet \
  --set stages.shake.time.end=19.5 --set bne.phase_field.phases=4 \
  --set 'render.size=[8.5, 12.0]' --set render.font_size=8
take "$runs/bne/phase_field.png" bne_phase_field_after.png

# the crater quick scene's collapse frame and local mean velocity field at 0.5 s into the collapse,
# every figure single column (a series shares its first figure's arrow scale)
columns=()
for k in 0 1 2 3 4 5 6 7; do columns+=(--set "output.figures.$k.style=\"single_column\""); done
"$sablier" run scenes/crater/quick.scene --out "$runs/crater" --quiet \
  --set stages.deposit.movie=false --set stages.collapse.movie=false "${columns[@]}"
take "$runs/crater/collapse_0.5s.png" crater_collapse_after.png
take "$runs/crater/velocity_0.5s.png" crater_field_after.png
rm -rf "$runs"
echo "publication figures: 3 in $out"
