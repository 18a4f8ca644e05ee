#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# run_accuracy.sh: what accuracy costs in time, in one command (docs/accuracy.md).
#
#   bench/run_accuracy.sh [--quick] [--build-dir DIR] [--out DIR]
#
# 1. Builds bench_accuracy, bench_effects and bench_render_accuracy_plot in Release
#    (default build dir: build).
# 2. bench_accuracy: every integrator (and velocity Verlet and symplectic Euler with
#    contact.onset = event) x dt = t_c / n; restitution and contact-duration errors
#    against 000 eqs. 3.22-3.24, energy drift over 100 elastic bounces, crater profile and height
#    against a converged reference -> OUT/accuracy.csv (summary tables on stdout).
# 3. bench_effects: time per particle-step with each effect declared or not -> OUT/effects.csv.
# 4. The work-precision plot -> OUT/accuracy.png and OUT/accuracy.pdf.
# Default OUT: bench/results. About 3-5 minutes on 2 cores; --quick is a smoke run (~1 min).
# The 1-minute load average before and after is printed: other work on the machine inflates the
# times (the CPU-time columns less so than wall time).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$root/build"
out="$root/bench/results"
quick=()
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) quick=(--quick) ;;
    --build-dir) build_dir=$2; shift ;;
    --out) out=$2; shift ;;
    -h | --help) sed -n '3,16p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run_accuracy.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
load() { cut -d' ' -f1 /proc/loadavg; }

echo "== build ($build_dir, Release)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j2 --target bench_accuracy bench_effects \
    bench_render_accuracy_plot >/dev/null
mkdir -p "$out"

model=$(awk -F: '/^model name/ { sub(/^ +/, "", $2); print $2; exit }' /proc/cpuinfo)
echo "== machine: $model, $(nproc) CPUs; load $(load)"
start=$(date +%s)

echo "== bench_accuracy (progress on stderr -> $out/accuracy.log)"
"$build_dir/bench/bench_accuracy" "${quick[@]}" --csv "$out/accuracy.csv" 2>"$out/accuracy.log" |
    tee "$out/accuracy-summary.md"

echo
echo "== bench_effects (load $(load))"
if [ ${#quick[@]} -gt 0 ]; then
    effects_args=(--grains 1000 --steps 200 --repeats 5)
else
    effects_args=(--grains 2000 --steps 1000 --repeats 9)
fi
"$build_dir/bench/bench_effects" "${effects_args[@]}" --csv "$out/effects.csv" |
    tee "$out/effects-summary.txt"

echo
echo "== plot"
"$build_dir/bench/bench_render_accuracy_plot" "$out/accuracy.csv" "$out/accuracy.png" \
    "$out/accuracy.pdf"
echo "== done in $(($(date +%s) - start)) s; load $(load); results in $out"
