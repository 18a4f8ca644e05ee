#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# threads_auto.sh: `sablier run --threads 1`, `--threads 2` and `--threads auto` on the same scene,
# on the machine as it is ("quiet") and with one competing CPU-bound process ("busy": `yes`
# pinned to the first CPU of this process's mask), and the ratios of their wall times.
#
#   bench/threads_auto.sh [--repeats K] [--deposit SECONDS] [--sablier PATH] [--scene FILE]
#                         [--threads-b N] [--work DIR]
#
# The scene (default scenes/crater/standard.scene: the standard crater's rain deposition, 7284
# grains in a 21 m box) runs its deposit stage only, for --deposit simulated seconds (default
# 0.5), the dig and the collapse skipped. Each repeat runs 1, N (--threads-b, default 2) and auto
# one after the other, the order turning from one repeat to the next, so that a drift of the
# machine reaches all three alike; the ratios are taken within a repeat (time over the one-thread
# run's) and printed as min / median over the K repeats (default 3), with each run's wall time
# (min / median: "process", measured outside it, start-up and figures included; "stage", the
# deposit's wall seconds in summary.json) and the step seconds auto spent on each count
# (summary.json's "thread_choices"). A ratio below 1 is faster than one thread. Not a test: the figures depend on the machine and what else runs.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=bench/lib.sh
source "$root/bench/lib.sh" # now, stats
repeats=3
deposit=0.5
sablier="$root/build/sablier"
scene="$root/scenes/crater/standard.scene"
threads_b=2
work=${TMPDIR:-/tmp}/sablier-threads-auto-$$
while [ $# -gt 0 ]; do
    case "$1" in
    --repeats) repeats=$2; shift ;;
    --deposit) deposit=$2; shift ;;
    --sablier) sablier=$2; shift ;;
    --scene) scene=$2; shift ;;
    --threads-b) threads_b=$2; shift ;;
    --work) work=$2; shift ;;
    -h | --help) sed -n '3,18p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "threads_auto.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ -x "$sablier" ] || { echo "threads_auto.sh: no sablier at $sablier (--sablier PATH)" >&2; exit 2; }
mkdir -p "$work"
busy_pid=""
cleanup() {
    [ -n "$busy_pid" ] && kill "$busy_pid" 2>/dev/null
    rm -rf "$work"
}
trap cleanup EXIT

# run LABEL THREADS: one run; prints its wall seconds and the deposit stage's
run() {
    local out="$work/$1" t0 t1
    rm -rf "$out"
    t0=$(now)
    "$sablier" run "$scene" --out "$out" --quiet --threads "$2" \
        --set "stages.deposit.time.end=$deposit" --set stages.dig.skip=true \
        --set stages.collapse.skip=true >"$work/$1.log" 2>&1 ||
        { echo "threads_auto.sh: run $1 failed: $(tail -3 "$work/$1.log")" >&2; exit 1; }
    t1=$(now)
    local stage # the deposit's own wall seconds in summary.json: no start-up, no figures
    stage=$(sed -n 's/.*"name": "deposit", .*"wall_seconds": \([0-9.e+-]*\),.*/\1/p' "$out/summary.json")
    awk -v a="$t0" -v b="$t1" -v s="$stage" 'BEGIN { printf "%.3f %.3f\n", b - a, s }'
}

# auto's step seconds on each count, from its summary.json: "1: 3.2 s, 2: 0.4 s"
auto_counts() {
    sed -n 's/.*"seconds_on": \[\(.*\)\]}.*/\1/p' "$1" |
        awk '{ gsub(/\], \[/, ";"); gsub(/[][]/, ""); n = split($0, p, ";");
               for (i = 1; i <= n; ++i) { split(p[i], q, ", "); printf "%s%s: %.2f s", (i > 1 ? ", " : ""), q[1], q[2] } }'
}

# column_stats LABEL FIELD NAME: the runs' seconds in field FIELD of $work/$cond.times, and
# their ratios to the one-thread runs of the same repeats
column_stats() {
    local mine one
    mine=$(awk -v l="$1" -v f="$2" '$1 == l { print $f }' "$work/$cond.times")
    one=$(awk -v f="$2" '$1 == "1" { print $f }' "$work/$cond.times")
    printf "%s %s s, ratio %s;" "$3" "$(stats <<<"$mine")" \
        "$(paste <(echo "$mine") <(echo "$one") | awk '{ printf "%.3f\n", $1 / $2 }' | stats)"
}

measure() { # measure CONDITION
    local cond=$1 r k label
    : >"$work/$cond.times"
    for ((r = 0; r < repeats; ++r)); do
        local order=("1" "$threads_b" "auto")
        for ((k = 0; k < 3; ++k)); do
            label=${order[$(((k + r) % 3))]}
            echo "$label $(run "$cond-$label" "$label")" >>"$work/$cond.times"
            [ "$label" = auto ] && echo "$r $(auto_counts "$work/$cond-auto/summary.json")" >>"$work/$cond.auto"
        done
    done
    echo "== $cond: $repeats repeats; seconds min / median; ratio to --threads 1 (same repeat) min / median"
    for label in 1 "$threads_b" auto; do
        printf "  --threads %-4s  %s\n" "$label" "$(column_stats "$label" 2 process) $(column_stats "$label" 3 stage)"
    done
    sed 's/^\([0-9]*\) /  auto, repeat \1: step seconds on each count: /' "$work/$cond.auto"
    rm -f "$work/$cond.auto"
}

echo "threads_auto.sh: $(basename "$scene"), deposit $deposit s, $(nproc) CPUs in the mask," \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
measure quiet
first_cpu=$(taskset -pc $$ 2>/dev/null | sed 's/.*: //; s/[-,].*//' || echo "")
if [ -n "$first_cpu" ] && command -v taskset >/dev/null; then
    taskset -c "$first_cpu" yes >/dev/null &
else
    yes >/dev/null &
fi
busy_pid=$!
measure busy
kill "$busy_pid" 2>/dev/null
busy_pid=""
echo "load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
