#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check_threads.sh THREADS SABLIER CASE WORK RENDER: golden case CASE (check.sh) run with
# `--threads THREADS`, or with `--threads-switch-every 50` when THREADS is `switch` (the count
# then cycles through 1, 2, 3 and 4 threads every 50 steps): the results are the same bits on any
# thread count (README.md, Determinism), so every output must be the recorded one.
set -uo pipefail
threads=$1
shift
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
case $threads in
switch) GOLDEN_THREADS="--threads-switch-every 50" ;;
*) GOLDEN_THREADS="--threads $threads" ;;
esac
GOLDEN_THREADS=$GOLDEN_THREADS exec bash "$here/check.sh" "$@"
