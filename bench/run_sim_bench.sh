#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# run_sim_bench.sh: the physics speed benchmark in one command.
#
#   bench/run_sim_bench.sh [--with-lammps] [--grains N] [--steps M] [--repeats K]
#                          [--warmup W] [--rounds R] [--pin CPU|none] [--machine NAME]
#                          [--build-dir DIR] [--fresh]
#
# 1. Builds bench_sim in Release (default build dir: build-bench).
# 2. Runs bench_sim: settled pile of N polydisperse disks (built once, cached in /tmp), one
#    thread, regularised Coulomb / tangential spring / frictionless; K repeats of M steps.
# 3. When `lmp` is installed, runs LAMMPS (bench/lammps/pile.in, one MPI rank) on the very same
#    settled pile with gran/hooke, gran/hooke/history and frictionless gran/hooke. With
#    --with-lammps, installs the Debian package `lammps` first if `lmp` is missing.
# 4. Prints one table with both codes and their ratio, and writes
#    bench/results/<machine>.csv (machine: --machine, default from /proc/cpuinfo + CPU count).
#
# Figures are million particle-steps per second, counting mobile grains only, best of K repeats
# (wall clock); the "cpu" columns divide by CPU time instead (less disturbed on a shared
# machine); ratio = sablier / LAMMPS. The 1-minute load average before and after is printed and stored: other work on
# the machine lowers the figures.
# Both codes run on one CPU (`taskset -c`, --pin; default the first CPU of the affinity mask;
# --pin none leaves them to the scheduler): on a guest whose two vCPUs ran at 52-58 and 71 M
# particle-steps/s, an unpinned LAMMPS landed on either and its figure moved by a third.
# --rounds R (default 1) runs steps 2 and 3 R times in turn, sablier then LAMMPS, so that a drift
# of a shared host reaches both codes alike: the table and the CSV hold each code's best round,
# and a line per law gives the R ratios taken within a round and their median (quote that one on
# a noisy host: LAMMPS's speed moved by a third from one process to the next on a host where
# sablier's moved by 1 %).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
with_lammps=0
grains=7000
steps=2000
repeats=5
rounds=1
pin=""
warmup=500
machine=""
build_dir="$root/build-bench"
fresh=()

while [ $# -gt 0 ]; do
    case "$1" in
    --with-lammps) with_lammps=1 ;;
    --grains) grains=$2; shift ;;
    --steps) steps=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --rounds) rounds=$2; shift ;;
    --pin) pin=$2; shift ;;
    --warmup) warmup=$2; shift ;;
    --machine) machine=$2; shift ;;
    --build-dir) build_dir=$2; shift ;;
    --fresh) fresh=(--fresh) ;;
    -h | --help) sed -n '3,21p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run_sim_bench.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done

if [ -z "$machine" ]; then
    model=$(awk -F: '/^model name/ { print $2; exit }' /proc/cpuinfo)
    machine=$(echo "$model" | tr 'A-Z' 'a-z' | sed -e 's/([^)]*)//g' -e 's/[^a-z0-9]\+/-/g' \
        -e 's/^-//' -e 's/-$//')-$(nproc)cpu
fi
load() { cut -d' ' -f1 /proc/loadavg; }

echo "== build ($build_dir, Release)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=ON >/dev/null
cmake --build "$build_dir" -j2 --target bench_sim >/dev/null

# The CPU both codes run on: the first of the affinity mask unless --pin names one (or none).
on_cpu=()
if [ "$pin" != none ] && command -v taskset >/dev/null 2>&1; then
    [ -n "$pin" ] || pin=$(taskset -pc $$ | sed 's/.*: *//; s/[-,].*//')
    on_cpu=(taskset -c "$pin")
    echo "== both codes pinned to CPU $pin (--pin)"
fi

work=$(mktemp -d /tmp/sablier-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
load_before=$(load)

if ! command -v lmp >/dev/null 2>&1 && [ "$with_lammps" = 1 ]; then
    echo "== installing LAMMPS (apt-get install -y lammps)"
    if [ "$(id -u)" = 0 ]; then
        apt-get install -y lammps >/dev/null
    else
        sudo apt-get install -y lammps >/dev/null
    fi
fi
have_lammps=0
command -v lmp >/dev/null 2>&1 && have_lammps=1

# LAMMPS rows in bench_sim's CSV columns (bench/lammps/row.awk).
lammps_row() { # model law log
    awk -v machine="$machine" -v law="$2" -v steps="$steps" -v repeats="$repeats" -v dt="$dt" \
        -f "$root/bench/lammps/row.awk" "$3"
}

# One round: bench_sim's laws into $work/round-R.csv, then LAMMPS's on the pile it wrote.
one_round() { # round
    echo "== sablier bench_sim, round $1 of $rounds (load $(load))"
    "${on_cpu[@]}" "$build_dir/bench/bench_sim" --grains "$grains" --steps "$steps" --repeats "$repeats" \
        --warmup "$warmup" --machine "$machine" --csv "$work/round-$1.csv" \
        --lammps-data "$work/pile.data" "${fresh[@]}" | tee "$work/sablier.txt"
    fresh=()
    dt=$(awk -F, 'NR == 2 { print $NF }' "$work/round-$1.csv")
    [ "$have_lammps" = 1 ] || return 0
    version=$( (lmp -h 2>/dev/null || true) | sed -n 's/^Large-scale[^-]* - //p')
    echo "== LAMMPS $version, 1 MPI rank, round $1 of $rounds (load $(load))"
    for pair in hooke:regularised hist:spring nofric:frictionless; do
        model=${pair%%:*}
        law=${pair##*:}
        (cd "$work" && "${on_cpu[@]}" lmp -in "$root/bench/lammps/pile.in" -var data "$work/pile.data" \
            -var model "$model" -var dt "$dt" -var steps "$steps" -var repeats "$repeats" \
            -var warmup "$warmup" -log "$work/lammps-$model.log" -screen none)
        lammps_row "$model" "$law" "$work/lammps-$model.log" >>"$work/round-$1.csv"
        cp "$work/lammps-$model.log" "$build_dir/bench/lammps-$model.log"
    done
    echo "== LAMMPS logs (timing breakdown): $build_dir/bench/lammps-*.log"
}

for ((r = 1; r <= rounds; r++)); do
    one_round "$r"
done
[ "$have_lammps" = 1 ] ||
    echo "== LAMMPS: lmp not installed (pass --with-lammps to install the Debian package)"
# Each code's best round per law (column 10: best M particle-steps/s), in the order of round 1.
awk -F, 'FNR == 1 { if (NR == 1) print; next }
    { key = $2 "," $3; if (!(key in best)) order[++n] = key
      if (!(key in best) || $10 + 0 > best[key] + 0) { best[key] = $10; row[key] = $0 } }
    END { for (i = 1; i <= n; i++) print row[order[i]] }' "$work"/round-*.csv >"$work/all.csv"
load_after=$(load)

echo
echo "== physics speed, million particle-steps/s, one core (machine $machine, load $load_before -> $load_after)"
awk -F, -v have="$have_lammps" '
    NR == 1 { next }
    $2 == "sablier" { law[++n] = $3; s[$3] = $10; sc[$3] = $12; cs[$3] = $13; bg[$3] = $17; bc[$3] = $18 }
    $2 == "lammps" { l[$3] = $10; lc[$3] = $12; cl[$3] = $13; lb[$3] = $20 }
    END {
        printf "%-13s %8s %8s %8s %8s %7s %7s %8s %8s %9s %10s\n", "law", "sablier", "sab_cpu",
            "lammps", "lmp_cpu", "ratio", "r_cpu", "cont/gr", "lmp_c/gr", "sab_B/gr", "sab_B/cont"
        for (i = 1; i <= n; i++) {
            k = law[i]
            if (have && (k in l))
                printf "%-13s %8.2f %8.2f %8.2f %8.2f %6.2fx %6.2fx %8.3f %8.3f %9.0f %10.0f\n", k,
                    s[k], sc[k], l[k], lc[k], s[k] / l[k], sc[k] / lc[k], cs[k], cl[k], bg[k], bc[k]
            else
                printf "%-13s %8.2f %8.2f %8s %8s %7s %7s %8.3f %8s %9.0f %10.0f\n", k, s[k],
                    sc[k], "-", "-", "-", "-", cs[k], "-", bg[k], bc[k]
        }
        if (have)
            for (k in lb) printf "# LAMMPS %s: %.0f B per atom (Per MPI rank memory allocation)\n", k, lb[k]
    }' "$work/all.csv"

if [ "$have_lammps" = 1 ] && [ "$rounds" -gt 1 ]; then
    echo "== ratio sablier / LAMMPS within each round, best repeat (then the median of the rounds)"
    for ((r = 1; r <= rounds; r++)); do cat "$work/round-$r.csv"; done | awk -F, '
        $1 == "machine" { round++; next }
        $2 == "sablier" { s[$3] = $10; if (!($3 in seen)) { seen[$3] = 1; law[++n] = $3 } }
        $2 == "lammps" { r[$3, round] = s[$3] / $10 }
        END {
            for (i = 1; i <= n; i++) {
                k = law[i]; m = 0; line = ""
                for (j = 1; j <= round; j++) { v[++m] = r[k, j]; line = line sprintf(" %.2fx", r[k, j]) }
                for (a = 1; a <= m; a++) for (b = a + 1; b <= m; b++) if (v[b] < v[a]) { t = v[a]; v[a] = v[b]; v[b] = t }
                med = m % 2 ? v[(m + 1) / 2] : 0.5 * (v[m / 2] + v[m / 2 + 1])
                printf "%-13s%s  median %.2fx\n", k, line, med
            }
        }'
fi

mkdir -p "$root/bench/results"
out="$root/bench/results/$machine.csv"
awk -F, -v OFS=, -v a="$load_before" -v b="$load_after" \
    'NR == 1 { print $0, "load_before", "load_after"; next } { print $0, a, b }' \
    "$work/all.csv" >"$out.tmp"
mv "$out.tmp" "$out"
echo "== wrote $out"
