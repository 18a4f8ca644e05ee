#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.pool_signal: SIGINT (and SIGTERM) to a multi-run command stops its members through the
# shared pool (app/driver/pool.c): exit 130 (143), no member process left, the members' table written
# with status `interrupted` for those not finished; --resume then runs only the unfinished ones.
# `sablier ensemble` on tests/cli/ensemble_fall.scene (one grain, without gravity, long enough
# per member that the signal comes while members run: about 5 and 10 s in Release (0.6 s each
# at a tenth of that let a member end between two polls on a busy machine).
# The signal waits for two finished members, not one: the pool runs the fine dt first, so the
# first two members have the same length and end together, and a look taken between the first's
# end and the second's could count the second as under way and see it gone at the re-check (seen
# once under `ctest -j2`). Once both have ended, the two members under way are the next two,
# started after them, and the first of those to end is a coarse one, a whole member's length
# (seconds of CPU, more on a busy machine) later: the look and the re-check fall in that window.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.pool_signal: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
long=1440000 end=$long
ensemble() { # ensemble OUT ARGS...: in the background, $! its pid
  "$sablier" ensemble "$scene" --dt 0.0078125,0.00390625 --seeds 3 --jobs 2 --observe trace.csv:y \
    --set time.end="$end" --set 'gravity=[0.0, 0.0]' --set output.energy_every=1000 \
    --set output.trace_every=1000 --out "$1" --quiet "${@:2}" >"$1.log" 2>&1 &
}
# members: the `sablier run` processes writing into OUT (their command lines name it)
members() { pgrep -f -- "--out $1/" | wc -l; }
# every process of the command: the driver, its pool's children, their members
processes() { pgrep -f -- "--out $1[ /]" | wc -l; }
finished() { grep -l '"status": "ok"' $(find "$1" -name summary.json 2>/dev/null) 2>/dev/null | wc -l; }
# members under way: their energy.csv.tmp is open (their signal handlers are set by then)
running() { find "$1" -name energy.csv.tmp 2>/dev/null | wc -l; }

# stop OUT SIGNAL: start the ensemble, wait until two members finished and two are under way,
# send SIGNAL; echoes the exit status
stop() {
  local out=$1 signal=$2
  ensemble "$out"
  local pid=$!
  local deadline=$((SECONDS + 600)) # 10 min: sanitizers on a busy machine take minutes
  while [ "$SECONDS" -lt "$deadline" ]; do
    # in this order: a finished member's energy.csv is renamed before its summary.json is
    # written, so two under way after two finished are members started after those ended
    [ "$(finished "$out")" -ge 2 ] && [ "$(running "$out")" -ge 2 ] &&
      [ "$(members "$out")" -ge 2 ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  [ "$(members "$out")" -ge 2 ] || { kill -KILL "$pid"; fail "$signal: no two members running"; }
  kill -"$signal" "$pid"
  wait "$pid"
  echo $?
}

rc=$(stop "$work/a" INT)
[ "$rc" = 130 ] || fail "SIGINT: exit $rc, expected 130: $(cat "$work/a.log")"
left=$(processes "$work/a")
[ "$left" = 0 ] || fail "SIGINT: $left processes left: $(pgrep -af -- "--out $work/a[ /]")"
[ -s "$work/a/members.csv" ] || fail "SIGINT: no members.csv"
ok=$(awk -F, 'NR > 1 && $4 == 0' "$work/a/members.csv" | wc -l)
stopped=$(awk -F, 'NR > 1 && $4 == "interrupted"' "$work/a/members.csv" | wc -l)
[ "$ok" -ge 2 ] && [ "$stopped" -ge 2 ] && [ $((ok + stopped)) = 6 ] ||
  fail "SIGINT: members.csv: $ok ok, $stopped interrupted (6 members): $(cat "$work/a/members.csv")"
# a member stopped while it ran saved its state (its own SIGINT handling)
[ -n "$(find "$work/a" -name '*.interrupted.state')" ] || fail "SIGINT: no member saved its state"

# --resume: only the unfinished members run; the finished ones keep their folders
done_before=$(finished "$work/a")
stamp=$work/a.stamp
touch "$stamp"
end=1000 # the members left run at once
ensemble "$work/a" --resume
wait $!
rc=$?
[ "$rc" = 0 ] || fail "--resume: exit $rc: $(cat "$work/a.log")"
[ "$(awk -F, 'NR > 1 && $4 == 0' "$work/a/members.csv" | wc -l)" = 6 ] ||
  fail "--resume: not every member ok: $(cat "$work/a/members.csv")"
rerun=$(find "$work/a" -name summary.json -newer "$stamp" | wc -l)
[ "$rerun" = $((6 - done_before)) ] ||
  fail "--resume ran $rerun members, expected the $((6 - done_before)) unfinished"

end=$long
rc=$(stop "$work/b" TERM)
[ "$rc" = 143 ] || fail "SIGTERM: exit $rc, expected 143: $(cat "$work/b.log")"
[ "$(processes "$work/b")" = 0 ] || fail "SIGTERM: processes left"
grep -q ',interrupted,' "$work/b/members.csv" || fail "SIGTERM: no member interrupted"
echo "cli.pool_signal: ok"
