#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.resume (docs/cli.md#periodic-checkpoints-and---resume): a run continued
# with --resume from its newest periodic checkpoint, or from an interruption, writes every .state
# and CSV byte for byte as the uninterrupted run; a stage that loads the previous stage's .state
# ends in the same bytes as the run that continued in memory; --resume without a checkpoint,
# with another scene or other --set values is refused with exit 2 before anything runs.
#
# resume.sh --outputs SABLIER SCENE WORK [--set K=V ...] (cli.resume_<family>): a scene of an
# experiment family, periodic checkpoints forced with --set output.checkpoint_every: a run lost
# after its last checkpoint (its later outputs gone, junk after the checkpoint's length in every
# file the checkpoint records) and a run interrupted by SIGINT, both continued with --resume,
# leave every output as the uninterrupted run does: each .state, CSV, JSON (summary.json
# without its timings, threads and provenance), dump file (.lammpstrj, .vtp, .pvd) and .vti,
# byte for byte.
set -u
fail() { echo "cli.resume: $*" >&2; exit 1; }

# summary.json without what differs between runs of the same scene: timings, the threads auto
# chose, provenance (and the thread choices after it)
summary_physics() {
  sed -e 's/"wall_seconds": [^,}]*//g' -e 's/"particle_steps_per_second": [^,}]*//g' \
    -e 's/"threads": [0-9]*//' \
    -e '/"provenance"/,$d' "$1"
}

# same_outputs A B: every output of A (recursively; not movies, figures, logs, the checkpoint
# record) is in B with the same bytes
same_outputs() {
  local a=$1 b=$2 n=0 f
  while IFS= read -r f; do
    case "$f" in
    summary.json)
      [ "$(summary_physics "$a/$f")" = "$(summary_physics "$b/$f")" ] ||
        fail "$b/$f differs from $a/$f (timings and provenance aside)" ;;
    *) cmp -s "$a/$f" "$b/$f" || fail "$b/$f differs from $a/$f" ;;
    esac
    n=$((n + 1))
  done < <(cd "$a" && find . -type f ! -name '*.mp4' ! -name '*.png' ! -name '*.pdf' \
    ! -name '*.svg' ! -name '*.log' ! -name checkpoint.txt ! -name manifest.txt | sed 's|^\./||' | sort)
  [ "$n" -ge 5 ] || fail "only $n outputs compared"
  [ -z "$(find "$b" -name '*.tmp' -o -name '*.interrupted.state')" ] ||
    fail "$b: left: $(find "$b" -name '*.tmp' -o -name '*.interrupted.state')"
}

if [ "${1:-}" = "--outputs" ]; then
  sablier=$2 scene=$3 work=$4
  shift 4
  rm -rf "$work"
  mkdir -p "$work"
  "$sablier" run "$scene" --out "$work/full" --quiet "$@" >"$work/full.log" 2>&1 ||
    fail "full run: $(cat "$work/full.log")"
  grep -q '^begin ' "$work/full/checkpoint.txt" || fail "no family or dump section in the checkpoint"
  # (1) lost after the last checkpoint: the stage's final state and the summary gone, junk
  # appended to every file the checkpoint records
  cp -r "$work/full" "$work/lost"
  stage=$(sed -n 's/^state \(.*\)\.checkpoint\.state$/\1/p' "$work/lost/checkpoint.txt")
  [ -n "$stage" ] || fail "the last checkpoint is not a periodic one: $(head -6 "$work/lost/checkpoint.txt")"
  rm -f "$work/lost/$stage.state" "$work/lost/summary.json"
  for f in energy.csv $(sed -n 's/^file \([^ ]*\) [0-9]*$/\1/p' "$work/lost/checkpoint.txt"); do
    echo "0.99,junk" >>"$work/lost/$f"
  done
  "$sablier" run "$scene" --out "$work/lost" --quiet --resume "$@" >"$work/lost.log" 2>&1 ||
    fail "resume: $(cat "$work/lost.log")"
  same_outputs "$work/full" "$work/lost"
  # (2) interrupted by SIGINT after the first checkpoint of that stage (wherever it lands: the
  # same bytes), then resumed
  "$sablier" run "$scene" --out "$work/cut" --quiet "$@" >"$work/cut.log" 2>&1 &
  pid=$!
  for _ in $(seq 1 3000); do
    grep -qx "state $stage.checkpoint.state" "$work/cut/checkpoint.txt" 2>/dev/null && break
    sleep 0.01
  done
  kill -INT "$pid" 2>/dev/null
  wait "$pid"
  rc=$?
  [ "$rc" = 130 ] || [ "$rc" = 0 ] || fail "interrupted run: exit $rc: $(cat "$work/cut.log")"
  "$sablier" run "$scene" --out "$work/cut" --quiet --resume "$@" >"$work/cut2.log" 2>&1 ||
    fail "resume after SIGINT (exit $rc): $(cat "$work/cut2.log")"
  same_outputs "$work/full" "$work/cut"
  echo "cli.resume: $(basename "$scene"): ok (interrupted run: exit $rc)"
  exit 0
fi

sablier=$1 scene=$2 other=$3 work=$4
rm -rf "$work"
mkdir -p "$work"

. "$(dirname "${BASH_SOURCE[0]}")/same_outputs.sh" || fail "same_outputs.sh not found" # same A B

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
