#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# collapse_threads.sh: the standard crater's collapse stage from a dug bed, on 1 and N threads,
# with its Cairo movie and without (`--set 'output.movie=[]'`), and the ratios of their wall
# times: what a movie costs a run on each thread count (docs/dev/scaling.md, "Frames").
#
#   bench/collapse_threads.sh [--rounds K] [--seconds S] [--state FILE] [--sablier PATH]
#                             [--threads-b N] [--bands 1|2] [--work DIR]
#
# The bed: --state names a dig.state of scenes/crater/standard.scene (`sablier run` writes it
# into its folder); without it the scene's deposit and dig run once first, on N threads (about
# 50-100 s on 2 cores). Each round runs the collapse's first S simulated seconds (default 2: 50
# frames at the scene's 25 per second; at least 1, the scene's last timed figure) four times, movie and no movie on 1 and N (--threads-b,
# default 2) threads, the order turned from one round to the next so that a drift of the machine
# reaches all alike; the ratio 1 / N is taken within a round and printed as min / median over the
# K rounds (default 2), with each run's process wall seconds, min / median. --bands sets
# SABLIER_BANDS for every run (default: unset, the drawing follows --threads). Not a test: the
# figures depend on the machine and what else runs.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=bench/lib.sh
source "$root/bench/lib.sh" # now, stats
rounds=2
seconds=2.0
state=""
sablier="$root/build/sablier"
scene="$root/scenes/crater/standard.scene"
threads_b=2
work=${TMPDIR:-/tmp}/sablier-collapse-threads-$$
while [ $# -gt 0 ]; do
    case "$1" in
    --rounds) rounds=$2; shift ;;
    --seconds) seconds=$2; shift ;;
    --state) state=$2; shift ;;
    --sablier) sablier=$2; shift ;;
    --threads-b) threads_b=$2; shift ;;
    --bands) export SABLIER_BANDS=$2; shift ;;
    --work) work=$2; shift ;;
    -h | --help) sed -n '3,18p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "collapse_threads.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ -x "$sablier" ] || { echo "collapse_threads.sh: no sablier at $sablier (--sablier PATH)" >&2; exit 2; }
mkdir -p "$work"
trap 'rm -rf "$work"' EXIT

if [ -z "$state" ]; then
    echo "collapse_threads.sh: the bed (deposit and dig on $threads_b threads) into $work/bed"
    "$sablier" run "$scene" --out "$work/bed" --quiet --threads "$threads_b" \
        --set stages.collapse.skip=true >"$work/bed.log" 2>&1 ||
        { echo "collapse_threads.sh: the bed failed: $(tail -3 "$work/bed.log")" >&2; exit 1; }
    state=$work/bed/dig.state
fi
[ -f "$state" ] || { echo "collapse_threads.sh: no state $state" >&2; exit 2; }
state=$(cd "$(dirname "$state")" && pwd)/$(basename "$state")

# run MOVIE THREADS: one collapse window; prints its process wall seconds
run() {
    local out="$work/$1-$2" t0 t1 extra=()
    [ "$1" = without ] && extra=(--set 'output.movie=[]')
    rm -rf "$out"
    t0=$(now)
    "$sablier" run "$scene" --out "$out" --quiet --threads "$2" --set stages.deposit.skip=true \
        --set stages.dig.skip=true --set "stages.collapse.load=$state" \
        --set "stages.collapse.time.end=$seconds" "${extra[@]}" >"$out.log" 2>&1 ||
        { echo "collapse_threads.sh: run $1 $2 failed: $(tail -3 "$out.log")" >&2; exit 1; }
    t1=$(now)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }'
}


echo "collapse_threads.sh: $seconds s of the collapse from $(basename "$state"), $rounds rounds," \
    "$(nproc) CPUs in the mask, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')," \
    "SABLIER_BANDS=${SABLIER_BANDS:-unset}, load $(cut -d' ' -f1-3 /proc/loadavg)"
: >"$work/times"
runs=("with 1" "with $threads_b" "without 1" "without $threads_b")
for ((r = 0; r < rounds; ++r)); do
    for ((k = 0; k < 4; ++k)); do
        # shellcheck disable=SC2086
        set -- ${runs[$(((k + r) % 4))]}
        wall=$(run "$1" "$2")
        echo "$r $1 $2 $wall" >>"$work/times"
    done
done
for movie in with without; do
    for t in 1 "$threads_b"; do
        printf "  movie %-7s --threads %-3s %s s\n" "$movie" "$t" \
            "$(awk -v m="$movie" -v t="$t" '$2 == m && $3 == t { print $4 }' "$work/times" | stats)"
    done
    ratios=$(for ((r = 0; r < rounds; ++r)); do
        awk -v r="$r" -v m="$movie" -v b="$threads_b" '$1 == r && $2 == m { s[$3] = $4 }
            END { printf "%.3f\n", s[1] / s[b] }' "$work/times"
    done)
    printf "  movie %-7s 1 -> %s threads: %s (min / median over the rounds: %s)\n" "$movie" \
        "$threads_b" "$(tr '\n' ' ' <<<"$ratios" | sed 's/ $//')" "$(stats <<<"$ratios")"
done
echo "load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
