#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# run_accuracy.sh: what accuracy costs in time, in one command (docs/accuracy.md).
#
#   bench/run_accuracy.sh [--quick] [--build-dir DIR] [--out DIR] [--ensemble | --ensemble-only]
#
# 1. Builds bench_accuracy, bench_effects and bench_render_accuracy_plot in Release
#    (default build dir: build).
# 2. bench_accuracy: every integrator (and velocity Verlet and symplectic Euler with
#    contact.onset = event) x dt = t_c / n; restitution and contact-duration errors
#    against 000 eqs. 3.22-3.24, energy drift over 100 elastic bounces, crater profile and height
#    against a converged reference -> OUT/accuracy.csv (summary tables on stdout).
# 3. bench_effects: time per particle-step with each effect declared or not -> OUT/effects.csv.
# 4. The work-precision plot -> OUT/accuracy.png and OUT/accuracy.pdf.
# 5. --ensemble (or --ensemble-only: this step alone): `sablier ensemble` of the reduced crater
#    (scenes/crater/small.scene, 300 grains: deposit, dig, collapse; 32 seeds) at dt = 2e-4 ..
#    2.5e-5 s (34-275 steps per contact; mean crater height, surface minimum, bed packing
#    fraction) and of the small Brazil-nut box (scenes/brazil_nut/small.scene, 8 seeds:
#    intruder height after 30 periods, rise rate) at dt = 1.6e-3 .. 2e-4 s (21-171 steps per
#    contact), and of the discharge protocol (scenes/discharge/rolling_fixed.scene, L = 25 d,
#    w = 3 d, 16 seeds: discharge size s, h after the discharge, pile size) at dt = 2e-3 ..
#    5e-4 (members are `sablier discharge` with discharge.dt_divisor = 0): each mean's shift
#    against the finest dt with Welch's 95 % interval, against CPU time ->
#    OUT/ensemble-{crater,bne,discharge}.csv, .json, .png, .pdf and -answers.txt (members in
#    out/ensemble-NAME/). About 7 CPU minutes, 4-6 minutes on 2 cores (--quick: 4 seeds, 2
#    dts each).
# Default OUT: bench/results. About 3-5 minutes on 2 cores; --quick is a smoke run (~1 min).
# The 1-minute load average before and after is printed: other work on the machine inflates the
# times (the CPU-time columns less so than wall time).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="$root/build"
out="$root/bench/results"
quick=()
ensemble=0
benches=1
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) quick=(--quick) ;;
    --build-dir) build_dir=$2; shift ;;
    --out) out=$2; shift ;;
    --ensemble) ensemble=1 ;;
    --ensemble-only) ensemble=1; benches=0 ;;
    -h | --help) sed -n '3,24p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run_accuracy.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
load() { cut -d' ' -f1 /proc/loadavg; }

echo "== build ($build_dir, Release)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=ON >/dev/null
targets=()
[ $benches = 1 ] && targets+=(bench_accuracy bench_effects bench_render_accuracy_plot)
[ $ensemble = 1 ] && targets+=(sablier)
cmake --build "$build_dir" -j2 --target "${targets[@]}" >/dev/null
mkdir -p "$out"

model=$(awk -F: '/^model name/ { sub(/^ +/, "", $2); print $2; exit }' /proc/cpuinfo)
echo "== machine: $model, $(nproc) CPUs; load $(load)"
start=$(date +%s)

# ensemble_run NAME SCENE DTS SEEDS KEYS [SET...]: one `sablier ensemble` over the time steps DTS,
# members in out/ensemble-NAME/, its tables and figure copied to OUT/ensemble-NAME.*
ensemble_run() {
    local name=$1 scene=$2 dts=$3 seeds=$4 keys=$5
    shift 5
    local members="$root/out/ensemble-$name" sets=() t0
    for s in "$@"; do sets+=(--set "$s"); done
    echo
    echo "== ensemble $name: $seeds seeds x dt $dts (load $(load))"
    local command=("$build_dir/sablier" ensemble "$root/$scene" --dt "$dts"
        --seeds "$seeds" --jobs 2 --quiet --observe "$keys" "${sets[@]}" --out "$members")
    echo "sablier ensemble $scene --dt $dts --seeds $seeds --jobs 2" \
        "--observe $keys ${sets[*]}"
    t0=$(date +%s)
    "${command[@]}" | tee "$out/ensemble-$name-answers.txt" ||
        echo "== ensemble $name: exit status $? (a member failed: see $members/*/seed-*/log.txt)"
    for f in csv json png pdf; do
        if [ -f "$members/ensemble.$f" ]; then cp "$members/ensemble.$f" "$out/ensemble-$name.$f"; fi
    done
    echo "== ensemble $name done in $(($(date +%s) - t0)) s; load $(load)"
}
ensemble_step() {
    # from near the stability limit (crater 2.2e-4 s, n = 32; Brazil nut 1.8e-3 s, n = 19) down
    # (a crater member costs 0.25-0.75 CPU s, a Brazil-nut member 1-4.3 s)
    local crater_seeds=32 bne_seeds=8 crater=2e-4,1e-4,5e-5,2.5e-5 bne=1.6e-3,8e-4,4e-4,2e-4
    if [ ${#quick[@]} -gt 0 ]; then crater_seeds=4 bne_seeds=4 crater=2e-4,5e-5 bne=1.6e-3,4e-4; fi
    ensemble_run crater scenes/crater/small.scene "$crater" "$crater_seeds" \
        crater.crater_height,crater.surface_min,bed.packing_fraction time.max_dt_fraction=0
    ensemble_run bne scenes/brazil_nut/small.scene "$bne" "$bne_seeds" \
        bne.json:end_height,bne.json:rise_rate
    # the discharge protocol at the thesis's smallest base (L = 25 d), one width; its reference
    # is near the thesis's own dt = sqrt(m_min/k_n)/50 = 6.2e-4 (members 2.5-10 CPU s)
    local discharge_seeds=16 discharge=2e-3,1e-3,5e-4
    if [ ${#quick[@]} -gt 0 ]; then discharge_seeds=4 discharge=2e-3,1e-3; fi
    ensemble_run discharge scenes/discharge/rolling_fixed.scene "$discharge" "$discharge_seeds" \
        discharges.0.s,discharges.0.h,deposition.pile 'discharge.widths=[3.0]'
}
if [ $benches = 0 ]; then
    ensemble_step
    echo "== done in $(($(date +%s) - start)) s; load $(load); results in $out"
    exit 0
fi

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
[ $ensemble = 1 ] && ensemble_step
echo "== done in $(($(date +%s) - start)) s; load $(load); results in $out"
