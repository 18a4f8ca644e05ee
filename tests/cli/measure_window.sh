#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.measure_window: a measure's windows at exact multiples of its cadence whatever the step, and
# a window that ends with its stage written at the stage's end (tests/cli/measure_window.scene:
# dt = 7e-4 s divides neither `every` = 0.05 s, nor `window`, nor the 4 s stage). Each window's
# row time is the mean of its samples' declared times.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.measure_window: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# times OUT: the distinct row times of OUT/profile.csv, one a line
times() { tail -n +2 "$1/profile.csv" | cut -d, -f1 | uniq | tr '\n' ' ' | sed 's/ $//'; }
check() { # check NAME EXPECTED [--set ...]: a run and its window times
  local name=$1 expected=$2
  shift 2
  "$sablier" run "$scene" --out "$work/$name" --quiet "$@" >"$work/$name.log" 2>&1 ||
    fail "$name: run failed: $(cat "$work/$name.log")"
  local got
  got=$(times "$work/$name")
  [ "$got" = "$expected" ] || fail "$name: window times [$got], expected [$expected]"
  # two nodes (bins) per window
  local rows=$(($(wc -l <"$work/$name/profile.csv") - 1)) words
  words=$(echo "$expected" | wc -w)
  [ "$rows" = $((2 * words)) ] || fail "$name: $rows rows, expected $((2 * words))"
}
check windows "0.525 1.525 2.525 3.525"
# one window as long as the stage: written at its end (was lost: only the header)
check whole "2.025" --set stages.run.measures.0.window=4.0
# a window whose end falls between two samples (every = 0.3 s: 3.9 s is the last sample) and
# ends with the stage
check between "2.1" --set stages.run.measures.0.every=0.3 --set stages.run.measures.0.window=4.0
# no window: every sample written, at its declared time, the last at the stage's end
"$sablier" run "$scene" --out "$work/samples" --quiet --set stages.run.measures.0.window=0 \
  --set stages.run.measures.0.every=0.5 >"$work/samples.log" 2>&1 ||
  fail "samples: run failed: $(cat "$work/samples.log")"
got=$(times "$work/samples")
[ "$got" = "0 0.5 1 1.5 2 2.5 3 3.5 4" ] || fail "samples: times [$got]"
echo "cli.measure_window: ok"
