#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# real_vs_bench.sh: cost per particle-step of a real `sablier run` against `bench_sim --wide`,
# at 7 000 and 70 000 grains (700 000 with --large), in wall time and in instructions.
#
#   bench/real_vs_bench.sh [--large] [--steps M] [--repeats K] [--deposit SECONDS]
#                          [--no-instructions] [--build-dir DIR] [--work DIR]
#
# Real run: the standard crater's rain deposition (scenes/crater/standard.scene, 7284 grains in
# a 21 m box), and copies f = 10 (100) times wider: the box 210 m (2100 m) wide, the rain's
# lattice 980 (9800) columns instead of 98 and max_count 72 840 (728 400), so every column sees
# the same rain and the same bed. Each is first run natively to t = --deposit (default 1.5 s:
# the lower half of the rain has landed, the rest still falls; the state is kept in --work and
# reused), then continued from that state (the stage's `load`) for 100 steps (A) and 100 + M
# steps (B, default M = 2000). A cost per particle-step is (B - A) / (grains x M), so that the
# start-up, the load, the first list build and the end of stage cancel, and the steps measured
# are the same simulated phase at every width; the window holds what a real stage does every
# step (energy rows every 1000 steps, the guard every 100, the chunks that end on them).
# Bench: `bench_sim --wide --grains N --only regularised` (a settled pile of the standard bed's
# height), 100 and 100 + M steps after no warm-up, the same difference.
#
# Time: the deposit stage's wall seconds in summary.json (real) and bench_sim's best_s of K
# repeats (default 2, the best of the (B - A) differences); wall time is noisy on a shared
# machine. Instructions (valgrind --tool=callgrind; --no-instructions skips them, they cost
# about 50 times the run): deterministic; the top functions of each difference are printed,
# per particle-step, with callgrind_annotate. The build is Release without rendering (Valgrind
# stops at an instruction in a library FFmpeg pulls in; figures are not part of a step).
# Under Valgrind the kernels are AVX2 (Valgrind hides AVX-512). Not a test.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
factors="1 10"
steps=2000
repeats=2
deposit=1.5
instructions=1
build_dir="$root/build-real"
work=${TMPDIR:-/tmp}/sablier-real-vs-bench
while [ $# -gt 0 ]; do
    case "$1" in
    --large) factors="1 10 100" ;;
    --steps) steps=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --deposit) deposit=$2; shift ;;
    --no-instructions) instructions=0 ;;
    --build-dir) build_dir=$2; shift ;;
    --work) work=$2; shift ;;
    -h | --help) sed -n '3,28p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "real_vs_bench.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
if [ "$instructions" = 1 ] && ! command -v valgrind >/dev/null 2>&1; then
    echo "real_vs_bench.sh: no valgrind: wall time only" >&2
    instructions=0
fi

echo "== build ($build_dir, Release, no rendering)"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSABLIER_BUILD_TESTS=ON \
    -DSABLIER_WITH_RENDER=OFF >/dev/null
cmake --build "$build_dir" -j2 --target sablier bench_sim >/dev/null
sablier=$build_dir/sablier
bench=$build_dir/bench/bench_sim
scene=$root/scenes/crater/standard.scene
mkdir -p "$work"
a=100
b=$((a + steps))
dt=1e-5 # the scene's time step
base=(--quiet --threads 1 --force --set stages.dig.skip=true --set stages.collapse.skip=true)

# widen F: the --set values of the scene F times wider (F = 1: none)
widen() {
    [ "$1" = 1 ] && return 0
    awk -v f="$1" 'BEGIN {
        # rain columns 2 r_pitch + gap = 0.210525 m apart, the first at x0 + 2 r_hi (sim/build.c):
        # 98 f columns end before x0 + 0.1728 + (98 f - 1 + 0.5) 0.210525
        printf "--set grains.box.x1=%.3f --set grains.rain.x1=%.4f --set grains.rain.max_count=%d\n",
            0.105 + 21.0 * f, 0.23 + 0.1728 + (98 * f - 0.5) * 0.210525, 7284 * f }'
}

# real_window F STEPS [valgrind...]: continue the deposited state for STEPS steps; prints the
# stage's wall seconds
real_window() {
    local f=$1 n=$2 out="$work/real-$1-$2"
    shift 2
    # shellcheck disable=SC2046
    "$@" "$sablier" run "$scene" --out "$out" "${base[@]}" $(widen "$f") \
        --set "stages.deposit.load=$work/deposit-$f.state" \
        --set "stages.deposit.time.end=$(awk -v n="$n" -v dt="$dt" 'BEGIN { print n * dt }')" \
        >"$out.log" 2>&1 || { echo "real_vs_bench.sh: run failed: $(tail -3 "$out.log")" >&2; exit 1; }
    sed -n 's/.*"name": "deposit", .*"wall_seconds": \([0-9.e+-]*\),.*/\1/p' "$out/summary.json"
}

# bench_window N STEPS [valgrind...]: bench_sim for STEPS steps; prints best_s
bench_window() {
    local n=$1 s=$2
    shift 2
    "$@" "$bench" --wide --grains "$n" --steps "$s" --repeats 1 --warmup 0 --only regularised \
        --csv "$work/bench-$n-$s.csv" >"$work/bench-$n-$s.log" 2>&1
    awk -F, 'NR == 2 { print $8 }' "$work/bench-$n-$s.csv"
}

# total_ir FILE: the instructions a callgrind output file counted
total_ir() { sed -n 's/^summary: \([0-9]*\)/\1/p;s/^totals: \([0-9]*\)/\1/p' "$1" | head -1; }

top_functions() { # A.out B.out PARTICLE_STEPS: the 8 largest self-cost differences
    local f
    for f in "$1" "$2"; do
        callgrind_annotate --auto=no --threshold=100 "$f" 2>/dev/null |
            awk '/^ *[0-9,]+ \(/ && /:/ { n = $1; gsub(",", "", n); s = $0
                sub(/^ *[0-9,]+ \([ 0-9.%]+\) +/, "", s); sub(/ \[.*$/, "", s); sub(/^.*\//, "", s)
                c[s] += n } END { for (k in c) print k "\t" c[k] }' | sort >"$f.tsv"
    done
    join -t "$(printf '\t')" -a1 -a2 -e0 -o 0,1.2,2.2 "$1.tsv" "$2.tsv" |
        awk -F'\t' -v ps="$3" '{ printf "      %8.2f  %s\n", ($3 - $2) / ps, $1 }' |
        sort -k1,1gr | awk 'NR <= 8' # all of its input: no SIGPIPE under pipefail
}

rows=$work/rows.csv
echo "kind,grains,ns_per_ps,ir_per_ps" >"$rows"
for f in $factors; do
    n=$((7284 * f))
    if [ ! -s "$work/deposit-$f.state" ]; then
        echo "== real $n grains: depositing to t = $deposit s (once; kept in $work)"
        # shellcheck disable=SC2046
        "$sablier" run "$scene" --out "$work/deposit-$f" "${base[@]}" $(widen "$f") \
            --set "stages.deposit.time.end=$deposit" >"$work/deposit-$f.log" 2>&1 ||
            { echo "real_vs_bench.sh: deposit failed: $(tail -3 "$work/deposit-$f.log")" >&2; exit 1; }
        mv "$work/deposit-$f/deposit.state" "$work/deposit-$f.state"
    fi
    best=""
    for _ in $(seq "$repeats"); do
        ta=$(real_window "$f" "$a")
        tb=$(real_window "$f" "$b")
        best=$(awk -v x="$ta" -v y="$tb" -v c="$best" 'BEGIN { d = y - x; print (c == "" || d < c) ? d : c }')
    done
    ir=0
    if [ "$instructions" = 1 ]; then
        real_window "$f" "$a" valgrind --tool=callgrind --callgrind-out-file="$work/cg-real-$f-a" >/dev/null
        real_window "$f" "$b" valgrind --tool=callgrind --callgrind-out-file="$work/cg-real-$f-b" >/dev/null
        ir=$(awk -v x="$(total_ir "$work/cg-real-$f-a")" -v y="$(total_ir "$work/cg-real-$f-b")" \
            -v ps="$((n * steps))" 'BEGIN { printf "%.2f", (y - x) / ps }')
    fi
    echo "real,$n,$(awk -v d="$best" -v ps="$((n * steps))" 'BEGIN { printf "%.2f", 1e9 * d / ps }'),$ir" >>"$rows"
    echo "== real $n grains: $(tail -n 1 "$rows")"
    [ "$instructions" = 1 ] && top_functions "$work/cg-real-$f-a" "$work/cg-real-$f-b" "$((n * steps))"

    m=$((7000 * f))
    best=""
    for _ in $(seq "$repeats"); do
        ta=$(bench_window "$m" "$a")
        tb=$(bench_window "$m" "$b")
        best=$(awk -v x="$ta" -v y="$tb" -v c="$best" 'BEGIN { d = y - x; print (c == "" || d < c) ? d : c }')
    done
    ir=0
    if [ "$instructions" = 1 ]; then
        bench_window "$m" "$a" valgrind --tool=callgrind --callgrind-out-file="$work/cg-bench-$f-a" >/dev/null
        bench_window "$m" "$b" valgrind --tool=callgrind --callgrind-out-file="$work/cg-bench-$f-b" >/dev/null
        ir=$(awk -v x="$(total_ir "$work/cg-bench-$f-a")" -v y="$(total_ir "$work/cg-bench-$f-b")" \
            -v ps="$((m * steps))" 'BEGIN { printf "%.2f", (y - x) / ps }')
    fi
    echo "bench,$m,$(awk -v d="$best" -v ps="$((m * steps))" 'BEGIN { printf "%.2f", 1e9 * d / ps }'),$ir" >>"$rows"
    echo "== bench $m grains: $(tail -n 1 "$rows")"
    [ "$instructions" = 1 ] && top_functions "$work/cg-bench-$f-a" "$work/cg-bench-$f-b" "$((m * steps))"
done

echo
echo "== cost per particle-step ($steps steps after $a, 1 thread; load $(cut -d' ' -f1 /proc/loadavg))"
awk -F, 'NR == 1 { next }
    { k[++n] = $1; g[n] = $2; t[n] = $3; i[n] = $4; if (!($1 in t0)) { t0[$1] = $3; i0[$1] = $4 } }
    END {
        printf "%-6s %8s %9s %8s %9s %8s\n", "kind", "grains", "ns/ps", "vs7k", "Ir/ps", "vs7k"
        for (r = 1; r <= n; r++)
            printf "%-6s %8d %9.2f %8.2f %9.1f %8s\n", k[r], g[r], t[r], t[r] / t0[k[r]], i[r],
                (i0[k[r]] > 0 ? sprintf("%.3f", i[r] / i0[k[r]]) : "-")
        for (r = 1; r < n; r += 2) # rows come in pairs: real, then bench, at each size
            printf "real / bench at %d grains: time %.2f, instructions %s\n", g[r], t[r] / t[r + 1],
                (i[r + 1] > 0 ? sprintf("%.3f", i[r] / i[r + 1]) : "-")
        if (n >= 4)
            printf "growth, real over bench: time %.2f, instructions %s\n",
                (t[n - 1] / t[1]) / (t[n] / t[2]),
                (i[1] > 0 && i[2] > 0 ? sprintf("%.3f", (i[n - 1] / i[1]) / (i[n] / i[2])) : "-")
    }' "$rows"
