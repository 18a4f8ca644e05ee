#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/gallery.sh: remakes every thesis figure of docs/gallery.md into OUT at a journal's
# column size, as PNG and PDF, named after the thesis and its figure number
# (000_fig7.12a_collapse.png and .pdf, ...).
#
#   scripts/gallery.sh [--reduced] [--pdf] [--sablier PATH] OUT
#
# Every grain figure is `style = "single_column"` (8.5 x 6.4 cm) or `"double_column"` (17.8 x
# 8.9 cm; the sediment bed with its profiles 17.8 x 6 cm), 8 pt text; every plot is one column
# wide (two for 2x2 panels) at its family's shape (docs/figures.md#plots). Full size: 300 dpi,
# each figure as PNG and PDF (`make gallery`).
# --reduced: the same print sizes at 100 dpi, shorter runs and one seed per Brazil-nut curve, PNG
# only (the ctest `gallery` and its references in tests/gallery/reference/).
# --pdf: the PDFs too when reduced (every figure and plot through render.plot_format = "pdf",
# beside its PNG); the figure lint reads them (tests/lint/figures.sh).
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
  -h | --help) sed -n '3,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
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
[ $reduced = 1 ] || pdf=1 # full size: PNG and PDF
# print keys of every run: the dpi (figures and plots), and with PDFs every PNG also as PDF
dpi=300
[ $reduced = 0 ] || dpi=100
plots=(--set "render.dpi=$dpi")
[ $pdf = 0 ] || plots+=(--set 'render.plot_format="pdf"')
runs=$out/.runs # hidden: `sablier diff` on OUT skips it
rm -rf "$runs"
mkdir -p "$runs"

# figure RUN FILE NAME: the run's FILE (a PNG) becomes OUT/NAME, and with PDFs, FILE.pdf becomes
# NAME.pdf when the run wrote one
figure() {
  local from=$runs/$1/$2 to=$out/$3
  cp "$from" "$to.tmp" && mv "$to.tmp" "$to"
  from=${from%.png}.pdf to=${to%.png}.pdf
  [ $pdf = 1 ] && [ -e "$from" ] || return 0
  cp "$from" "$to.tmp" && mv "$to.tmp" "$to"
}

# columns STYLE K...: --set of the scene's output.figures K... to a column preset
columns() {
  local style=$1 k
  shift
  for k in "$@"; do
    printf -- '--set\noutput.figures.%d.style="%s"\n' "$k" "$style"
  done
}

# 000: crater collapse, the quick bed (1500 grains); the energy panels of the deposit (fig. 6.15)
crater() {
  mapfile -t extra < <(columns single_column 0 1 2 3 4 5 6 7)
  "$sablier" run scenes/crater/quick.scene --out "$runs/crater" --quiet "${plots[@]}" \
    --set 'output.energy_stage="deposit"' \
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
  # double-column wide, 6 cm high: the bed (40 d x 16 d) and its two profile panels fill it
  local extra=(--set 'output.figures.0.size=[17.8, 6.0]' --set output.figures.0.font_size=8)
  [ $reduced = 0 ] || extra+=(--set stages.settle.time.end=5 --set stages.flow.time.end=5)
  "$sablier" run scenes/sediment/viscous.scene --out "$runs/sediment" --quiet \
    --set stages.flow.movie=false "${extra[@]}" "${plots[@]}"
  figure sediment bed.png 002_sediment_profiles.png
}

# 004: an open pile (L = 25 d, rolling resistance) and its discharge through w = 2.2 d
discharge() {
  "$sablier" discharge scenes/discharge/rolling_fixed.scene --width 2.2 --figures \
    --out "$runs/discharge" --quiet --set 'render.style="double_column"' "${plots[@]}"
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
