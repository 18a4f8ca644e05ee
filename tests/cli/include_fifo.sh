#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.include_fifo: a scene that @includes a FIFO, and a scene that is a FIFO, are refused with
# exit 2 (at the @include's line for the first) instead of blocking on the pipe.
set -u
sablier=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.include_fifo: $*" >&2; exit 1; }
mkfifo "$work/pipe.inc" "$work/pipe.scene"
cat >"$work/scene.scene" <<SCENE
name = "fifo";
seed = 1;
@include "pipe.inc"
SCENE
timeout 20 "$sablier" check "$work/scene.scene" >/dev/null 2>"$work/err.txt"
rc=$?
[ "$rc" = 2 ] || fail "include of a FIFO: exit $rc, expected 2: $(cat "$work/err.txt")"
grep -q "scene.scene:3: @include \"pipe.inc\": cannot read .*not a regular file" "$work/err.txt" ||
  fail "include of a FIFO: $(cat "$work/err.txt")"
timeout 20 "$sablier" check "$work/pipe.scene" >/dev/null 2>"$work/err.txt"
rc=$?
[ "$rc" = 2 ] || fail "a FIFO as the scene: exit $rc, expected 2: $(cat "$work/err.txt")"
grep -q "pipe.scene: cannot read scene file: not a regular file" "$work/err.txt" ||
  fail "a FIFO as the scene: $(cat "$work/err.txt")"
echo "cli.include_fifo: ok"
