#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/gallery.sh: remakes every thesis figure of docs/gallery.md into OUT, one PNG per figure
# named after the thesis and its figure number (000_fig7.12a_collapse.png, ...).
#
#   scripts/gallery.sh [--reduced] [--pdf] [--sablier PATH] OUT
#
# --reduced: small images and shorter runs (the ctest `gallery` and its references in
# tests/gallery/reference/); without it, the scenes' own sizes and durations (`make gallery`).
# --pdf: the figures as PDF where sablier writes one (plots through render.plot_format, frame
# figures through their format), named as the PNGs with .pdf; the figure lint reads them
# (tests/lint/figures.sh).
# The runs' own output folders go to OUT/.runs/ (hidden, so `sablier diff` on OUT compares the
# gallery only). Exit status: 0, or that of the first failing run.
set -euo pipefail

reduced=0
pdf=0
sablier=""
out=""
while [ $# -gt 0 ]; do
  case "$1" in
  --reduced) reduced=1 ;;
  --pdf) pdf=1 ;;
  --sablier) sablier=${2:?--sablier needs a path}; shift ;;
  -h | --help) sed -n '3,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  -*) echo "gallery.sh: unknown option $1" >&2; exit 2 ;;
  *) out=$1 ;;
  esac
  shift
done
[ -n "$out" ] || { echo "usage: scripts/gallery.sh [--reduced] [--pdf] [--sablier PATH] OUT" >&2; exit 2; }
out=$(realpath -m "$out")
[ -z "$sablier" ] || sablier=$(realpath "$sablier")
cd "$(dirname "$0")/.." # the scenes' paths are relative to the repository root
[ -n "$sablier" ] || sablier=$PWD/build/sablier
[ -x "$sablier" ] || { echo "gallery.sh: no sablier at $sablier (build it first)" >&2; exit 2; }
plots=() # --pdf: every plot also as PDF
[ $pdf = 0 ] || plots=(--set 'render.plot_format="pdf"')
runs=$out/.runs # hidden: `sablier diff` on OUT skips it
rm -rf "$runs"
mkdir -p "$runs"

# figure RUN FILE NAME: the run's FILE becomes OUT/NAME (with --pdf, FILE.pdf becomes NAME.pdf,
# when the run wrote one)
figure() {
  local from=$runs/$1/$2 to=$out/$3
  if [ $pdf = 1 ]; then
    from=${from%.png}.pdf to=${to%.png}.pdf
    [ -e "$from" ] || return 0
  fi
  cp "$from" "$to.tmp" && mv "$to.tmp" "$to"
}

# sizes N W H: --set of the figures 0..N-1 of a scene's output.figures to W x H when reduced,
# and to PDF with --pdf
sizes() {
  local n=$1 w=$2 h=$3
  for ((k = 0; k < n; ++k)); do
    [ $reduced = 0 ] ||
      printf -- '--set\noutput.figures.%d.width=%d\n--set\noutput.figures.%d.height=%d\n' "$k" "$w" "$k" "$h"
    [ $pdf = 0 ] || printf -- '--set\noutput.figures.%d.format="pdf"\n' "$k"
  done
}

# 000: crater collapse, the quick bed (1500 grains)
crater() {
  mapfile -t extra < <(sizes 8 240 160)
  "$sablier" run scenes/crater/quick.scene --out "$runs/crater" --quiet "${plots[@]}" \
    --set stages.deposit.movie=false --set stages.collapse.movie=false "${extra[@]}"
  figure crater energy_panels.png 000_fig6.15_energy.png
  figure crater settled.png 000_fig6.22_settled_bed.png
  figure crater cavity.png 000_fig6.24_cavity.png
  figure crater collapse_0.2s.png 000_fig7.12a_collapse.png
  figure crater collapse_0.5s.png 000_fig7.12b_collapse.png
  figure crater collapse_1.0s.png 000_fig7.12c_collapse.png
  figure crater velocity_0.2s.png 000_fig7.9a_velocity_field.png
  figure crater velocity_0.5s.png 000_fig7.9b_velocity_field.png
  figure crater crater.png 000_fig7.27_crater.png
  figure crater profiles.png 000_fig7.30_profiles.png
}

# 002 ch. 5: Brazil nut, rise curves in the small box (300 grains)
bne() {
  local seeds=3
  [ $reduced = 0 ] || seeds=1
  "$sablier" bne scenes/brazil_nut/small.scene --seeds $seeds --vary bne.gamma=1.5,3 \
    --out "$runs/bne_gamma" --quiet "${plots[@]}"
  figure bne_gamma rise.png 002_fig22_rise_gamma.png
  "$sablier" bne scenes/brazil_nut/small_density.scene --seeds $seeds \
    --vary species.intruder.density=0.1061032954,0.318309886183791,0.9549296586 \
    --out "$runs/bne_density" --quiet "${plots[@]}"
  figure bne_density rise.png 002_figs23-24_rise_density.png
  "$sablier" bne scenes/brazil_nut/small.scene --seeds $seeds --vary species.wall.mu=0,0.5 \
    --out "$runs/bne_walls" --quiet "${plots[@]}"
  figure bne_walls rise.png 002_fig25_rise_smooth_walls.png
  "$sablier" bne scenes/brazil_nut/small_frictionless.scene --seeds $seeds \
    --out "$runs/bne_frictionless" --quiet "${plots[@]}"
  figure bne_frictionless rise.png 002_fig26_rise_frictionless.png
}

# 002 ch. 6-7: bed-load transport, the bed with its fluid and grain profiles
sediment() {
  local extra=()
  [ $reduced = 0 ] || extra=(--set stages.settle.time.end=5 --set stages.flow.time.end=5
    --set output.figures.0.width=480 --set output.figures.0.height=200)
  "$sablier" run scenes/sediment/viscous.scene --out "$runs/sediment" --quiet \
    --set stages.flow.movie=false "${extra[@]}" "${plots[@]}"
  figure sediment bed.png 002_sediment_profiles.png
}

# 004: an open pile (L = 25 d, rolling resistance) and its discharge through w = 2.2 d
discharge() {
  local extra=()
  [ $reduced = 0 ] || extra=(--set render.width=480 --set render.height=270)
  "$sablier" discharge scenes/discharge/rolling_fixed.scene --width 2.2 --figures \
    --out "$runs/discharge" --quiet "${extra[@]}" "${plots[@]}"
  figure discharge pile.png 004_fig2.12a_pile.png
  figure discharge w2.2.png 004_fig2.12b_discharged.png
}

# two lanes (the machine's two cores; bne runs its samples two at a time too)
crater >"$runs/crater.log" 2>&1 &
lane=$!
bne
sediment
discharge
wait $lane || { cat "$runs/crater.log" >&2; exit 1; }
echo "gallery: $(find "$out" -maxdepth 1 -name "*.png" -o -maxdepth 1 -name "*.pdf" | wc -l) figures in $out"
