#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# bench/plot_vs_matplotlib.sh: the same profile.csv (the crater quick scene's free-surface
# profiles) drawn by sablier at single-column size (bench_app_plot_profile) and by matplotlib
# with its defaults (bench/plot_profile_matplotlib.py), PNG and PDF each; prints the time per
# figure of both and the fonts each PDF embeds (pdffonts). docs/figures.md#sablier-and-matplotlib.
#
#   bench/plot_vs_matplotlib.sh [BUILD_DIR] [REPEATS] [OUT_DIR]
#
# BUILD_DIR (default build) holds sablier and bench/bench_app_plot_profile; OUT_DIR (default
# BUILD_DIR/plot_vs_matplotlib) gets the run and the four figures. matplotlib comes from
# Debian's python3-matplotlib, which CI does not install:
#   SABLIER_SETUP_EXTRA="python3-matplotlib" bash scripts/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:-build}")
repeats=${2:-20}
out=$(realpath -m "${3:-$build/plot_vs_matplotlib}")
python=/usr/bin/python3 # Debian's, with its python3-matplotlib
[ -x "$python" ] || python=python3
"$python" -c "import matplotlib" 2>/dev/null || {
  echo "plot_vs_matplotlib: no matplotlib; install it with" >&2
  echo "  SABLIER_SETUP_EXTRA=python3-matplotlib bash scripts/setup.sh" >&2
  exit 2
}
mkdir -p "$out"
if [ ! -s "$out/run/profile.csv" ]; then # the reduced gallery's crater run (scripts/gallery.sh)
  "$build/sablier" run scenes/crater/quick.scene --out "$out/run" --quiet \
    --set stages.deposit.movie=false --set stages.collapse.movie=false
fi
echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
"$build/bench/bench_app_plot_profile" "$out/run" "$out" "$repeats"
"$python" bench/plot_profile_matplotlib.py "$out/run/profile.csv" "$out" "$repeats"
# one cold process each, as a user runs them (matplotlib's import included)
for tool in sablier matplotlib; do
  start=$(date +%s.%N)
  if [ $tool = sablier ]; then
    "$build/bench/bench_app_plot_profile" "$out/run" "$out" 1 >/dev/null
  else
    "$python" bench/plot_profile_matplotlib.py "$out/run/profile.csv" "$out" 1 >/dev/null
  fi
  ms=$(bc -l <<<"($(date +%s.%N) - $start) * 1000")
  printf '%s: %.0f ms for one figure in a new process\n' "$tool" "$ms"
done
for pdf in "$out/profiles.pdf" "$out/profiles_matplotlib.pdf"; do
  command -v pdffonts >/dev/null || break
  echo "$(basename "$pdf"): $(pdffonts "$pdf" | tail -n +3 | cut -c38-55 | sed 's/ *$//' | sort -u | paste -sd, -)"
done
ls -l "$out"/profiles*.png "$out"/profiles*.pdf | awk '{print $5, $NF}'
