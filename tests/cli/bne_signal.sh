#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.bne_signal: SIGINT to `sablier bne` (through the shared pool, app/driver/pool.c) stops its runs:
# exit 130, samples.csv written (through a temporary name: no .tmp left) with a row per run and
# the status `interrupted` for the runs that did not finish, the stopped runs' states saved.
# The shake stage is long enough that no run finishes before the signal.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.bne_signal: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
out=$work/o
"$sablier" bne "$scene" --seeds 3 --jobs 2 --set stages.settle.time.end=3 \
  --set stages.shake.time.end=100000 --out "$out" --quiet >"$work/log" 2>&1 &
pid=$!
# two runs under way: their energy.csv.tmp is open (their signal handlers are set by then)
for _ in $(seq 1 1200); do
  [ "$(find "$out" -name energy.csv.tmp 2>/dev/null | wc -l)" -ge 2 ] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.05
done
[ "$(find "$out" -name energy.csv.tmp 2>/dev/null | wc -l)" -ge 2 ] ||
  { kill -KILL "$pid"; fail "no two runs under way: $(cat "$work/log")"; }
kill -INT "$pid"
wait "$pid"
rc=$?
[ "$rc" = 130 ] || fail "exit $rc, expected 130: $(cat "$work/log")"
[ -z "$(pgrep -f -- "--out $out")" ] || fail "processes left"
head -1 "$out/samples.csv" | grep -q '^value,seed,status,' || fail "samples.csv: no status column"
rows=$(awk -F, 'NR > 1 && $3 == "interrupted"' "$out/samples.csv" | wc -l)
[ "$rows" = 3 ] || fail "samples.csv: $rows runs interrupted, expected 3: $(cat "$out/samples.csv")"
[ -z "$(find "$out" -name '*.tmp')" ] || fail "a .tmp file left: $(find "$out" -name '*.tmp')"
[ "$(find "$out" -name '*.interrupted.state' | wc -l)" -ge 2 ] || fail "no run saved its state"
echo "cli.bne_signal: ok"
