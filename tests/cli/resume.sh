#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.resume (issue 18 part 2, docs/cli.md#periodic-checkpoints-and---resume): a run continued
# with --resume from its newest periodic checkpoint, or from an interruption, writes every .state
# and CSV byte for byte as the uninterrupted run; a stage that loads the previous stage's .state
# ends in the same bytes as the run that continued in memory; --resume without a checkpoint,
# with another scene or other --set values is refused with exit 2 before anything runs.
set -u
sablier=$1 scene=$2 other=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "cli.resume: $*" >&2; exit 1; }

# same A B: every .state and .csv of run A is in B with the same bytes
same() {
  local a=$1 b=$2 n=0
  for f in "$a"/*.state "$a"/*.csv; do
    cmp -s "$f" "$b/${f#"$a"/}" || fail "$b/${f#"$a"/} differs from $f"
    n=$((n + 1))
  done
  [ "$n" -ge 6 ] || fail "only $n outputs compared"
}

"$sablier" run "$scene" --out "$work/full" --quiet >"$work/full.log" 2>&1 ||
  fail "full run: $(cat "$work/full.log")"
grep -q '^state tilt.checkpoint.state$' "$work/full/checkpoint.txt" || fail "no checkpoint in tilt"

# (1) A run lost after its last checkpoint (the final state, the summary gone; energy.csv with
# rows after the checkpoint): --resume writes the same bytes.
cp -r "$work/full" "$work/lost"
rm "$work/lost/tilt.state" "$work/lost/summary.json"
echo "0.99,junk" >>"$work/lost/energy.csv"
"$sablier" run "$scene" --out "$work/lost" --quiet --resume >"$work/lost.log" 2>&1 ||
  fail "resume: $(cat "$work/lost.log")"
same "$work/full" "$work/lost"
grep -q '"status": "ok"' "$work/lost/summary.json" || fail "resumed summary.json not ok"

# (1b) interrupted by SIGINT in a longer run, then resumed: the same bytes as its full run
long="--set stages.tilt.time.end=8"
"$sablier" run "$scene" --out "$work/long" --quiet $long >"$work/long.log" 2>&1 ||
  fail "long run: $(cat "$work/long.log")"
"$sablier" run "$scene" --out "$work/cut" --quiet $long >"$work/cut.log" 2>&1 &
pid=$!
for _ in $(seq 1 600); do
  if [ -f "$work/cut/energy.csv.tmp" ] && [ "$(wc -l <"$work/cut/energy.csv.tmp")" -gt 80 ]; then break; fi
  sleep 0.05
done
kill -INT "$pid"
wait "$pid"
rc=$?
if [ "$rc" = 130 ]; then
  grep -q 'interrupted.state$' "$work/cut/checkpoint.txt" || fail "no record of the interruption"
  "$sablier" run "$scene" --out "$work/cut" --quiet $long --resume >"$work/cut2.log" 2>&1 ||
    fail "resume after SIGINT: $(cat "$work/cut2.log")"
  [ -z "$(find "$work/cut" -name '*.interrupted.state')" ] || fail "interrupted state left"
else
  echo "cli.resume: the run ended (exit $rc) before SIGINT; resume after it instead"
  "$sablier" run "$scene" --out "$work/cut" --quiet $long --resume >"$work/cut2.log" 2>&1 ||
    fail "resume: $(cat "$work/cut2.log")"
fi
same "$work/long" "$work/cut"

# (2) the second stage loading the first one's state: the same final bytes (the source feeds
# the first stage only: a source's own state is not in a .state file)
fill_only='sources.0.stages=["fill"]'
"$sablier" run "$scene" --out "$work/cont" --quiet --set "$fill_only" >"$work/cont.log" 2>&1 ||
  fail "continuous run: $(cat "$work/cont.log")"
"$sablier" run "$scene" --out "$work/load" --quiet --set "$fill_only" --set stages.fill.skip=true \
  --set "stages.tilt.load=\"$work/cont/fill.state\"" >"$work/load.log" 2>&1 ||
  fail "load run: $(cat "$work/load.log")"
cmp -s "$work/cont/tilt.state" "$work/load/tilt.state" ||
  fail "tilt loaded from fill.state differs from the continuous run"

# (3) refused: no checkpoint, no folder, other --set values, another scene file
expect2() {
  local what=$1 pattern=$2
  shift 2
  "$@" >"$work/err.log" 2>&1
  local rc=$?
  [ "$rc" = 2 ] || fail "$what: exit $rc, expected 2: $(cat "$work/err.log")"
  grep -q -- "$pattern" "$work/err.log" || fail "$what: no '$pattern' in: $(cat "$work/err.log")"
}
mkdir -p "$work/empty"
expect2 "no checkpoint" "no checkpoint in" "$sablier" run "$scene" --out "$work/empty" --resume
[ -z "$(ls "$work/empty")" ] || fail "no checkpoint: files written: $(ls "$work/empty")"
expect2 "no folder" "no output folder" "$sablier" run "$scene" --out "$work/none" --resume
[ ! -e "$work/none" ] || fail "no folder: the folder was created"
expect2 "other --set" "scene differs" "$sablier" run "$scene" --out "$work/lost" --resume \
  --set seed=9
expect2 "other scene" "another scene file" "$sablier" run "$other" --out "$work/lost" --resume
cmp -s "$work/full/tilt.state" "$work/lost/tilt.state" || fail "a refused resume changed outputs"
echo "cli.resume: ok"
