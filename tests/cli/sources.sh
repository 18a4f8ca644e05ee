#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.sources.*: insertion sources at the CLI.
#   threads    the hopper (shortened, still inserting) and sources_heavy.scene (fed by sources
#              alone) on 1, 2, 3 and 8 threads: every .state and .csv byte for byte as one
#              thread's (grains added mid-run once wrote past the threaded contact pass's buffers)
#   auto_dt    a scene fed by sources alone with the automatic time step: `check` prints the
#              step the sources' grains need (it printed 0 s and a contact time of inf) and `run`
#              steps and inserts (it ran 0 steps, inserted nothing and said ok)
#   rate_bound a rate the region cannot hold per step (`--set sources.0.rate=1e12`): refused at
#              load with the location and the bound, exit 2, nothing written (it ran forever)
#   interrupt  SIGTERM while a source tries a million places per grain in a crowded region: the
#              run stops within 5 s, exit 143, "interrupted" (the insertion ignored the signal)
set -u
sablier=$1 mode=$2 dir=$3 root=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.sources.$mode: $*" >&2; exit 1; }
heavy=$dir/sources_heavy.scene
hopper=$root/scenes/hopper/hopper.scene

case $mode in
threads)
  . "$dir/same_outputs.sh" || fail "same_outputs.sh not found" # same A B [MIN]
  for threads in 1 2 3 8; do
    "$sablier" run "$hopper" --out "$work/hopper$threads" --quiet --threads "$threads" \
      --set stages.fill.time.end=2 --set 'output.movie=[]' \
      --set output.checkpoint_every=0.5 >"$work/hopper$threads.log" 2>&1 ||
      fail "hopper --threads $threads: exit $?: $(cat "$work/hopper$threads.log")"
    "$sablier" run "$heavy" --out "$work/heavy$threads" --quiet --threads "$threads" \
      >"$work/heavy$threads.log" 2>&1 ||
      fail "sources_heavy --threads $threads: exit $?: $(cat "$work/heavy$threads.log")"
  done
  grep -q '"inserted": [1-9]' "$work/hopper1/summary.json" || fail "the hopper inserted nothing"
  for threads in 2 3 8; do
    same "$work/hopper1" "$work/hopper$threads" 3
    same "$work/heavy1" "$work/heavy$threads" 3
  done
  ;;
auto_dt)
  "$sablier" check "$heavy" >"$work/check.txt" 2>&1 || fail "check: exit $?: $(cat "$work/check.txt")"
  grep -q 'time step *[0-9.e+-]* s (chosen from steps_per_contact)' "$work/check.txt" ||
    fail "no automatic time step in: $(cat "$work/check.txt")"
  grep -Eq 'time step +0 s|contact time +inf' "$work/check.txt" && fail "a time step of 0 or a contact time of inf: $(cat "$work/check.txt")"
  # the lightest grain: species small (1.27 kg/m^2), r = 0.3 m, k_n 2000 N/m, e_n 0.3; the
  # pair's contact time over steps_per_contact = 20
  grep -q 'time step *0.00159[0-9]* s' "$work/check.txt" ||
    fail "not the sources' time step: $(cat "$work/check.txt")"
  "$sablier" run "$heavy" --out "$work/run" --quiet --set stages.top.time.end=0.1 \
    >"$work/run.log" 2>&1 || fail "run: exit $?: $(cat "$work/run.log")"
  s=$work/run/summary.json
  grep -q '"status": "ok"' "$s" || fail "summary.json not ok"
  grep -q '"name": "pour", "inserted": [1-9][0-9][0-9]' "$s" || fail "the pour inserted under 100: $(cat "$s")"
  [ "$(wc -l <"$work/run/energy.csv")" -gt 10 ] || fail "energy.csv has no rows: the run did not step"
  ;;
rate_bound)
  "$sablier" check "$hopper" --set sources.0.rate=1e12 >"$work/check.txt" 2>&1
  rc=$?
  [ "$rc" = 2 ] || fail "check: exit $rc, expected 2: $(cat "$work/check.txt")"
  timeout 60 "$sablier" run "$hopper" --out "$work/out" --set sources.0.rate=1e12 >"$work/err.txt" 2>&1
  rc=$?
  [ "$rc" = 2 ] || fail "run: exit $rc, expected 2: $(cat "$work/err.txt")"
  for want in "--set sources.0.rate" "rate. 1e+12 grains/s asks 1e+09 grains a step" \
    "holds at most [0-9]* grains of radius 0.45: at most [0-9.e+]* grains/s"; do
    grep -q -- "$want" "$work/err.txt" || fail "no '$want' in: $(cat "$work/err.txt")"
  done
  [ ! -e "$work/out" ] || fail "the refused run wrote $work/out"
  # a count alone is one step's insertion: bounded the same way, at its line
  sed 's/rate = 40.0;/count = 100000;/' "$hopper" >"$work/count.scene"
  "$sablier" check "$work/count.scene" >"$work/count.txt" 2>&1
  rc=$?
  [ "$rc" = 2 ] || fail "count: exit $rc, expected 2: $(cat "$work/count.txt")"
  grep -q "count.scene:[0-9]*: .*count. 100000 alone .* holds at most [0-9]* grains" "$work/count.txt" ||
    fail "count: no bound in: $(cat "$work/count.txt")"
  # the largest rate the message gives is accepted
  bound=$(sed -n 's/.*: at most \([0-9.e+]*\) grains\/s.*/\1/p' "$work/err.txt")
  "$sablier" check "$hopper" --set "sources.0.rate=$bound" >"$work/ok.txt" 2>&1 ||
    fail "the bound $bound itself is refused: $(cat "$work/ok.txt")"
  ;;
interrupt)
  # 100 grains a step into a region as large as the box, a million tries per grain: once the
  # region is crowded a step's insertion takes minutes
  sed -e 's/region = \[1.0, 0.5, 9.0, 4.0\]; rate = 50.0;/region = [1.0, 0.5, 9.0, 11.0]; rate = 1e5; attempts = 1000000;/' \
    -e 's/end = 5.0;/end = 0.1;/' "$dir/insert_dense.scene" >"$work/full.scene"
  grep -q 'attempts = 1000000' "$work/full.scene" || fail "the scene was not edited"
  "$sablier" run "$work/full.scene" --out "$work/out" --quiet --threads 1 >"$work/log.txt" 2>&1 &
  pid=$!
  for _ in $(seq 1 200); do # until the feed stage has begun (20 s at most)
    grep -q 'stage settle:' "$work/log.txt" && break
    sleep 0.1
  done
  sleep 2
  kill -TERM "$pid"
  for _ in $(seq 1 50); do # 5 s
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    kill -KILL "$pid"
    fail "still running 5 s after SIGTERM"
  fi
  wait "$pid"
  rc=$?
  [ "$rc" = 143 ] || fail "exit $rc, expected 143: $(cat "$work/log.txt")"
  grep -q '"status": "interrupted"' "$work/out/summary.json" || fail "summary.json not interrupted"
  ;;
*) fail "unknown mode" ;;
esac
echo "cli.sources.$mode: ok"
