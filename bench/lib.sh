# SPDX-License-Identifier: MIT
# lib.sh: what the shell benchmarks share (bench/threads_auto.sh, bench/collapse_threads.sh);
# sourced, not run.
# shellcheck shell=bash

# now: the wall clock, seconds with nanoseconds
now() { date +%s.%N; }

# stats: min and median of the numbers on stdin, "MIN / MEDIAN"
stats() { sort -g | awk '{ v[NR] = $1 } END { m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.3f / %.3f", v[1], m }'; }
