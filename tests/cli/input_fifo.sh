#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.input_fifo: every input file is opened through one helper (sim_open_input) that
# refuses anything but a regular file before reading, so a FIFO given as a state (render, export),
# an image (diff), a grains file or a stage's checkpoint (`load`) exits 2 at once with "not a
# regular file" instead of blocking on the pipe. `timeout` turns a regression into a failure.
set -u
sablier=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.input_fifo: $*" >&2; exit 1; }
mkfifo "$work/pipe.state" "$work/pipe.png" "$work/pipe.csv"
# expect_refused NAME COMMAND...: exit 2 within the timeout, "not a regular file" on stderr
expect_refused() {
  local name=$1
  shift
  timeout 20 "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  [ "$rc" = 2 ] || fail "$name: exit $rc, expected 2 (124: it blocked): $(cat "$work/$name.err")"
  grep -q "not a regular file" "$work/$name.err" || fail "$name: message: $(cat "$work/$name.err")"
}
expect_refused export "$sablier" export "$work/pipe.state" -o "$work/out.csv"
[ ! -e "$work/out.csv" ] || fail "export: an output was written"
if ! "$sablier" --version | grep -q "render: not built"; then
  expect_refused render "$sablier" render "$work/pipe.state" -o "$work/out.png"
  [ ! -e "$work/out.png" ] || fail "render: a figure was written"
  expect_refused diff "$sablier" diff "$work/pipe.png" "$work/pipe.png"
fi
common='name = "fifo"; seed = 1; mass_model = "disk"; effects = [];
species = ( { name = "grain"; density = 1000.0; k_n = 1e4; gamma_n = 1.0; } );
time = { dt = 1e-4; end = 0.1; };'
printf '%s\ngrains = { file = "pipe.csv"; };\n' "$common" >"$work/grains.scene"
expect_refused grains "$sablier" check "$work/grains.scene"
grep -q "pipe.csv:1: cannot read the grains file: not a regular file" "$work/grains.err" ||
  fail "grains: $(cat "$work/grains.err")"
printf '%s\ngrains = { list = ( { x = 0.0; y = 0.0; r = 0.1; } ); };
stages = ( { name = "a"; }, { name = "b"; load = "pipe.state"; } );\n' "$common" >"$work/load.scene"
expect_refused load "$sablier" check "$work/load.scene"
grep -q "load.scene:5: .*pipe.state.*not a regular file" "$work/load.err" ||
  fail "load: $(cat "$work/load.err")"
echo "cli.input_fifo: ok"
