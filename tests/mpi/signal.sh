#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# mpi.signal SABLIER SCENE WORK WITH_MPI: a signal while both worker ranks of `mpirun -n 3 sablier
# ensemble` run a member: rank 0 passes the stop on to every busy worker (app/driver/pool_mpi.c), so
# both members stop at once and save their state, members.csv is written with every member
# `interrupted` and no process is left. SIGINT to rank 0 alone (the workers get nothing from
# mpirun: without the stop their members ran to their end), then SIGINT and SIGTERM to mpirun;
# rank 0's own exit status, 130, is mpirun's when mpirun got no signal. The members (tests/cli/ensemble_fall.scene
# without gravity, as cli.pool_signal) take seconds each, so none ends on its own before the
# signal. mpirun's own exit status is 1 (docs/cluster.md). Exit 77 (skipped) without MPI, under
# the sanitizers, or without mpirun (as tests/mpi/check.sh).
set -uo pipefail
sablier=$1 scene=$2 work=$3 with_mpi=$4
case ${with_mpi^^} in ON | 1 | TRUE | YES) ;; *) echo "mpi: skipped ($with_mpi)"; exit 77 ;; esac
command -v mpirun >/dev/null || { echo "mpi: skipped: no mpirun on PATH"; exit 77; }
fail() { echo "mpi.signal: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# rank0 MPIRUN_PID: the pid of rank 0 (a child of mpirun whose environment names rank 0)
rank0() {
  local p
  for p in $(pgrep -P "$1"); do
    tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=0' && echo "$p"
  done
}
check() { # check SIGNAL mpirun|rank0
  local out=$work/$1-$2
  mpirun --allow-run-as-root --oversubscribe -n 3 "$sablier" ensemble "$scene" \
    --dt 0.0078125,0.00390625 --seeds 2 --observe trace.csv:y --set time.end=360000 \
    --set 'gravity=[0.0, 0.0]' --set output.energy_every=1000 --set output.trace_every=1000 \
    --out "$out" --quiet >"$out.log" 2>&1 &
  local pid=$!
  # both members under way: their energy.csv.tmp is open (their signal handlers are set by then)
  for _ in $(seq 1 1200); do
    [ "$(find "$out" -name energy.csv.tmp 2>/dev/null | wc -l)" -ge 2 ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  [ "$(find "$out" -name energy.csv.tmp 2>/dev/null | wc -l)" -ge 2 ] ||
    { kill -KILL "$pid"; fail "$1: no two members under way: $(cat "$out.log")"; }
  local target=$pid
  [ "$2" = rank0 ] && target=$(rank0 "$pid")
  [ -n "$target" ] || { kill -KILL "$pid"; fail "$1: no rank 0 among $(pgrep -P "$pid")"; }
  kill -"$1" "$target"
  wait "$pid"
  local rc=$?
  [ "$2" = mpirun ] || [ "$rc" = 130 ] || fail "$1 to rank 0: mpirun exit $rc, expected 130"
  sleep 0.2
  [ -z "$(pgrep -f -- "--out $out")" ] || fail "$1: processes left: $(pgrep -af -- "--out $out")"
  [ -s "$out/members.csv" ] || fail "$1: no members.csv: $(cat "$out.log")"
  [ "$(awk -F, 'NR > 1 && $4 == "interrupted"' "$out/members.csv" | wc -l)" = 4 ] ||
    fail "$1: not every member interrupted: $(cat "$out/members.csv")"
  [ "$(find "$out" -name '*.interrupted.state' | wc -l)" = 2 ] ||
    fail "$1: the two running members did not both save their state"
}
check INT rank0
check INT mpirun
check TERM mpirun
echo "mpi.signal: ok"
