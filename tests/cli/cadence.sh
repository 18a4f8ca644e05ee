#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.cadence_huge: a cadence longer than any stage (energy_every = 1e308, trace_every = 1e300)
# means the first and last rows only, never a row every step through an overflowed conversion.
set -u
sablier=$1 tiny=$2 work=$3
rm -rf "$work"
"$sablier" run "$tiny" --out "$work" --quiet --set output.energy_every=1e308 \
  --set output.trace_every=1e300 --set time.end=0.01 >"$work.log" 2>&1 ||
  { echo "cli.cadence_huge: run failed: $(cat "$work.log")" >&2; exit 1; }
rows=$(($(wc -l <"$work/energy.csv") - 1))
[ "$rows" = 2 ] || { echo "cli.cadence_huge: energy.csv has $rows rows, expected 2 (start, end)" >&2; exit 1; }
rows=$(($(wc -l <"$work/trace.csv") - 1))
[ "$rows" = 1 ] || { echo "cli.cadence_huge: trace.csv has $rows rows, expected 1 (start)" >&2; exit 1; }
echo "cli.cadence_huge: ok"
