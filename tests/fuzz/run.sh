#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs each libFuzzer harness of BUILD (configured with -DSABLIER_FUZZ=ON, clang) from its
# committed seed corpus (tests/fuzz/corpus/<name>/) for a bounded number of inputs with a fixed
# seed, so a run is reproducible; fails on any crash, leak, timeout or out-of-memory finding
# (the input is kept in BUILD/fuzz/findings/). SECONDS bounds each harness: six of them at 75 s
# keep CI's fuzzing under 8 minutes. Usage: run.sh BUILD [RUNS] [SECONDS]
set -euo pipefail
build=$1 runs=${2:-${SABLIER_FUZZ_RUNS:-10000}} seconds=${3:-${SABLIER_FUZZ_SECONDS:-75}}
here=$(cd "$(dirname "$0")" && pwd)
findings=$build/fuzz/findings
mkdir -p "$findings"
status=0
for name in scene state png grains set cli; do
  exe=$build/tests/fuzz/fuzz_$name
  if [ ! -x "$exe" ]; then
    echo "fuzz: fuzz_$name not built (rendering off?), skipped"
    continue
  fi
  work=$build/fuzz/corpus_$name # new inputs go here, the committed corpus stays as it is
  quiet= # fuzz_cli: its usage messages go nowhere (libFuzzer's own reports still print)
  [ "$name" = cli ] && quiet=-close_fd_mask=2
  rm -rf "$work" && mkdir -p "$work"
  echo "== fuzz_$name: $runs inputs at most, $seconds s at most, seed 1"
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
       LSAN_OPTIONS=suppressions=$here/lsan.supp \
       "$exe" -seed=1 -runs="$runs" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
         -malloc_limit_mb=1024 -max_len=8192 -print_final_stats=1 $quiet \
         -artifact_prefix="$findings/${name}-" "$work" "$here/corpus/$name" 2>"$build/fuzz/$name.log"; then
    echo "fuzz: fuzz_$name FOUND A PROBLEM; input in $findings, log $build/fuzz/$name.log:" >&2
    grep -E "ERROR|SUMMARY|==[0-9]+==|Test unit written" "$build/fuzz/$name.log" | head -20 >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$build/fuzz/$name.log" | tr '\n' ' '
    echo
  fi
done
exit $status
