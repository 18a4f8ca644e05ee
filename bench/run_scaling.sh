#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# run_scaling.sh: cost per particle-step against size, at the standard bed's height.
#
#   bench/run_scaling.sh [--quick] [--sizes "N1 N2 ..."] [--threads "1 T"] [--steps M]
#                        [--repeats K] [--lammps-max N] [--ranks "1 2"] [--build-dir DIR]
#                        [--csv PATH]
#
# Each size N is a settled pile of N polydisperse disks as high as the 7000-grain standard pile,
# in a box whose width grows with N (bench_sim --wide: copies of the settled standard pile side by
# side, each in its compartment, so every size has the same contacts and motion per grain). On each
# pile: bench_sim with the regularised Coulomb law on 1 thread and on all cores, and LAMMPS
# (gran/hooke, bench/lammps/pile.in) on 1 and 2 MPI ranks for N <= --lammps-max, M steps after
# M/4 warm-up steps, best of K repeats.
#
# Columns: M/s = million particle-steps per second of wall time (mobile grains; best repeat),
# ns/ps = nanoseconds per particle-step (wall), vs7k = that cost over the same code's and
# worker count's at 7000 grains, cpu_ns/ps = the same per CPU second (all threads or ranks),
# rebuild/k = neighbour-list builds per 1000 steps, B/grain = peak resident memory of bench_sim
# over N (for LAMMPS: its "Per MPI rank memory allocation" times the ranks, over N).
#
# Modes: --quick = sizes 1000 7000 70000, 500 steps, 2 repeats, LAMMPS up to 7000 (a few
# minutes); the default (full) = 1000 7000 70000 700000 1001000, 2000 steps, 3 repeats, LAMMPS
# up to 70000 (the 1e6 point alone takes minutes per run). The first run of a size builds and
# caches its pile in /tmp (the 7000-grain tile's deposition, about a minute, once).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sizes="1000 7000 70000 700000 1001000"
steps=2000
repeats=3
lammps_max=70000
threads="1 $(nproc)"
ranks="1 2"
build_dir="$root/build-bench"
csv=""
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) sizes="1000 7000 70000"; steps=500; repeats=2; lammps_max=7000 ;;
    --sizes) sizes=$2; shift ;;
    --threads) threads=$2; shift ;;
    --steps) steps=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --lammps-max) lammps_max=$2; shift ;;
    --ranks) ranks=$2; shift ;;
    --build-dir) build_dir=$2; shift ;;
    --csv) csv=$2; shift ;;
    -h | --help) sed -n '3,27p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run_scaling.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ "$(nproc)" -gt 1 ] || threads=1
threads=$(tr ' ' '\n' <<<"$threads" | awk 'NF && !seen[$1]++' | tr '\n' ' ')
warmup=$((steps / 4))
load() { cut -d' ' -f1 /proc/loadavg; }

echo "== build ($build_dir, Release)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=ON >/dev/null
cmake --build "$build_dir" -j2 --target bench_sim >/dev/null
bench=$build_dir/bench/bench_sim

work=$(mktemp -d /tmp/sablier-scaling.XXXXXX)
trap 'rm -rf "$work"' EXIT
mpirun_root=()
[ "$(id -u)" != 0 ] || mpirun_root=(--allow-run-as-root)
have_lammps=0
command -v lmp >/dev/null 2>&1 && have_lammps=1
echo "n,code,workers,steps,mps_best,ns_per_ps,cpu_ns_per_ps,rebuilds_per_1000,bytes_per_grain" \
    >"$work/rows.csv"
load_before=$(load)

for n in $sizes; do
    echo "== $n grains (load $(load))"
    # the pile (built and cached on the first call) and its LAMMPS data file
    "$bench" --wide --grains "$n" --steps 1 --repeats 1 --warmup 0 --only regularised \
        --lammps-data "$work/pile-$n.data" >/dev/null
    for t in $threads; do
        "$bench" --wide --grains "$n" --threads "$t" --steps "$steps" --repeats "$repeats" \
            --warmup "$warmup" --only regularised --csv "$work/s.csv" >"$work/s.txt"
        rss=$(sed -n 's/^# peak resident memory \([0-9]*\) kB.*/\1/p' "$work/s.txt")
        awk -F, -v n="$n" -v t="$t" -v rss="$rss" 'NR == 2 {
            printf "%d,sablier,%d,%d,%.3f,%.3f,%.3f,%.3f,%.0f\n", n, t, $6, $10, 1000 / $10,
                1000 / $12, $16, 1024 * rss / $4 }' "$work/s.csv" >>"$work/rows.csv"
        tail -n 1 "$work/rows.csv"
    done
    dt=$(awk -F, 'NR == 2 { print $NF }' "$work/s.csv")
    [ "$have_lammps" = 1 ] && [ "$n" -le "$lammps_max" ] || continue
    for r in $ranks; do
        launch=(lmp)
        [ "$r" = 1 ] || launch=(mpirun "${mpirun_root[@]}" -np "$r" lmp)
        (cd "$work" && "${launch[@]}" -in "$root/bench/lammps/pile.in" -var data "pile-$n.data" \
            -var model hooke -var dt "$dt" -var steps "$steps" -var repeats "$repeats" \
            -var warmup "$warmup" -log "$work/lammps.log" -screen none) </dev/null
        awk -v machine=scaling -v law=regularised -v steps="$steps" -v repeats="$repeats" \
            -v dt="$dt" -f "$root/bench/lammps/row.awk" "$work/lammps.log" |
            awk -F, -v n="$n" -v r="$r" -v steps="$steps" '{
                printf "%d,lammps,%d,%d,%.3f,%.3f,%.3f,%.3f,%.0f\n", n, r, steps, $10,
                    1000 / $10, 1000 * r / $12, $16, $20 * r * ($4 + $5) / $4 }' \
                >>"$work/rows.csv"
        tail -n 1 "$work/rows.csv"
    done
done
load_after=$(load)

echo
echo "== cost per particle-step against size, regularised Coulomb (load $load_before -> $load_after)"
awk -F, 'NR == 1 { next }
    { row[++k] = $0; if ($1 == 7000) ref[$2 "," $3] = $6 }
    END {
        printf "%9s %-8s %3s %6s %8s %8s %6s %10s %10s %8s\n", "grains", "code", "w", "steps",
            "M/s", "ns/ps", "vs7k", "cpu_ns/ps", "rebuild/k", "B/grain"
        for (i = 1; i <= k; i++) {
            split(row[i], f, ",")
            key = f[2] "," f[3]
            rel = (key in ref) ? sprintf("%.2f", f[6] / ref[key]) : "-"
            printf "%9d %-8s %3d %6d %8.2f %8.2f %6s %10.2f %10.2f %8d\n", f[1], f[2], f[3], f[4],
                f[5], f[6], rel, f[7], f[8], f[9]
        }
    }' "$work/rows.csv"
if [ -n "$csv" ]; then
    cp "$work/rows.csv" "$csv"
    echo "== wrote $csv"
fi
