#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.hard.* (docs/physics.md, "Hard cases"): the CLI-level hard cases.
#   insert_dense     a source whose region lies inside a settled bed: the run ends well (exit 0),
#                    every grain it cannot place without overlap is skipped and counted
#                    (inserted + skipped = rate t), none inserted into an overlap that explodes
#   chute_unbounded  a frictionless chute that accelerates without bound: exit 1, the message
#                    naming the step, the time and the cause; the last good state saved
#   resume_threads   a run checkpointed with --threads 1 and resumed with --threads 2 (and 3):
#                    every .state and .csv byte for byte as the uninterrupted run
set -u
sablier=$1 mode=$2 dir=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.hard.$mode: $*" >&2; exit 1; }

case $mode in
insert_dense)
  "$sablier" run "$dir/insert_dense.scene" --out "$work/out" --quiet 2>"$work/err.txt" ||
    fail "exit $?: $(cat "$work/err.txt")"
  s="$work/out/summary.json"
  grep -q '"status": "ok"' "$s" || fail "summary.json not ok"
  inserted=$(sed -n 's/.*"inserted": \([0-9]*\).*/\1/p' "$s")
  skipped=$(sed -n 's/.*"skipped": \([0-9]*\).*/\1/p' "$s")
  [ -n "$inserted" ] && [ -n "$skipped" ] || fail "no source counts in $s"
  # 50 grains/s for 2 s; a grain is placed only where it touches nothing: the bed fills the
  # region, so at most a few find a void
  [ $((inserted + skipped)) -eq 100 ] || fail "inserted $inserted + skipped $skipped != 100"
  [ "$skipped" -ge 90 ] || fail "only $skipped of 100 skipped (inserted $inserted)"
  echo "cli.hard.insert_dense: inserted $inserted, skipped $skipped"
  ;;
chute_unbounded)
  "$sablier" run "$dir/chute_unbounded.scene" --out "$work/out" --quiet 2>"$work/err.txt"
  rc=$?
  [ "$rc" = 1 ] || fail "exit $rc, expected 1: $(cat "$work/err.txt")"
  for want in "stage slide: simulation failed at step [0-9]* (t = [0-9.]* s)" \
    "above the blow-up bound 20 m/s" "the flow accelerates without bound" \
    "a chute above its angle of repose" "last good state saved to"; do
    grep -q "$want" "$work/err.txt" || fail "no '$want' in: $(cat "$work/err.txt")"
  done
  # the runner's time is the failure's own (not the last good check's it rolled back to)
  grep -q "failed at step [0-9]* (t = \([0-9.]*\) s), grain [0-9]*: step [0-9]* (t = \1 s)" \
    "$work/err.txt" || fail "the step and time of the runner and of sim differ: $(cat "$work/err.txt")"
  [ -f "$work/out/slide.last_good.state" ] || fail "no last good state"
  grep -q '"status": "unstable"' "$work/out/summary.json" ||
    fail "summary.json does not record the failure"
  cat "$work/err.txt"
  ;;
resume_threads)
  scene=$dir/resume.scene
  . "$dir/same_outputs.sh" || fail "same_outputs.sh not found" # same A B
  "$sablier" run "$scene" --out "$work/full" --quiet --threads 1 >"$work/full.log" 2>&1 ||
    fail "full run: $(cat "$work/full.log")"
  grep -q '^state tilt.checkpoint.state$' "$work/full/checkpoint.txt" ||
    fail "no checkpoint in tilt"
  for threads in 2 3; do
    # lost after its last checkpoint (written with one thread), resumed with more
    cp -r "$work/full" "$work/lost$threads"
    rm "$work/lost$threads/tilt.state" "$work/lost$threads/summary.json"
    "$sablier" run "$scene" --out "$work/lost$threads" --quiet --resume --threads "$threads" \
      >"$work/lost$threads.log" 2>&1 || fail "resume --threads $threads: $(cat "$work/lost$threads.log")"
    same "$work/full" "$work/lost$threads"
  done
  ;;
*) fail "unknown mode" ;;
esac
echo "cli.hard.$mode: ok"
