#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.output_files: outputs are only ever regular files written through a temporary
# name. `export` and `render` refuse an -o target that is a symbolic link or a device (exit 2,
# before anything runs: the link and the device left as they were); a link left at a run's
# PATH.tmp is replaced, never written through; a full disk (the shim full_disk_shim.so makes the
# chosen temporary file /dev/full) exits 3, as docs/cli.md says, for run, export and render, with
# no truncated file committed.
set -u
sablier=$1 tiny=$2 shim=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.output_files: $*" >&2; exit 1; }
render=1
"$sablier" --version | grep -q "render: not built" && render=0
"$sablier" run "$tiny" --out "$work/run" --quiet >"$work/run.log" 2>&1 || fail "run: $(cat "$work/run.log")"
state=$(ls "$work/run"/*.state | head -n 1)
echo "precious" >"$work/outside.txt"
ln -s "$work/outside.txt" "$work/link.csv"
ln -s "$work/outside.txt" "$work/link.png"
# expect_refused NAME COMMAND...: exit 2 and "cannot write" on stderr
expect_refused() {
  local name=$1
  shift
  "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  [ "$rc" = 2 ] || fail "$name: exit $rc, expected 2: $(cat "$work/$name.err")"
  grep -q "cannot write" "$work/$name.err" || fail "$name: message: $(cat "$work/$name.err")"
}
expect_refused export_link "$sablier" export "$state" -o "$work/link.csv"
[ -L "$work/link.csv" ] || fail "export: the link was replaced"
[ "$(cat "$work/outside.txt")" = precious ] || fail "export: wrote through the link"
[ "$render" = 0 ] || expect_refused render_link "$sablier" render "$state" -o "$work/link.png"
[ -L "$work/link.png" ] || fail "render: the link was replaced"
[ "$(cat "$work/outside.txt")" = precious ] || fail "render: wrote through the link"
# a character device (a copy of /dev/null) as the target: needs root for mknod
if mknod "$work/null.csv" c 1 3 2>/dev/null && mknod "$work/null.png" c 1 3 2>/dev/null; then
  expect_refused export_device "$sablier" export "$state" -o "$work/null.csv"
  [ -c "$work/null.csv" ] || fail "export: the device was replaced by a regular file"
  [ "$render" = 0 ] || expect_refused render_device "$sablier" render "$state" -o "$work/null.png"
  [ -c "$work/null.png" ] || fail "render: the device was replaced by a regular file"
else
  echo "cli.output_files: not root: the device targets skipped"
fi
[ -z "$(find "$work" -maxdepth 1 -name '*.tmp')" ] || fail "a .tmp file was left"
# a link at a run's temporary name: replaced by the run's own file, the target untouched
mkdir -p "$work/t" && ln -s "$work/outside.txt" "$work/t/energy.csv.tmp"
"$sablier" run "$tiny" --out "$work/t" --quiet >"$work/t.log" 2>&1 || fail "run over a .tmp link: $(cat "$work/t.log")"
[ "$(cat "$work/outside.txt")" = precious ] || fail "run: wrote through the .tmp link"
[ -f "$work/t/energy.csv" ] && [ ! -L "$work/t/energy.csv" ] || fail "run: energy.csv not a file"
# a full disk: exit 3 and no truncated file (the shim needs the ASan runtime not to be first)
if [ -w /dev/full ] && [ -f "$shim" ]; then
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0"
  full() { # full NAME SUFFIX COMMAND...: exit 3, "disk full" on stderr
    local name=$1 suffix=$2
    shift 2
    SABLIER_TEST_FULL=$suffix LD_PRELOAD=$shim "$@" >"$work/$name.out" 2>"$work/$name.err"
    local rc=$?
    [ "$rc" = 3 ] || fail "$name: full disk: exit $rc, expected 3: $(cat "$work/$name.err")"
    grep -q "disk full" "$work/$name.err" || fail "$name: message: $(cat "$work/$name.err")"
  }
  full run_full energy.csv.tmp "$sablier" run "$tiny" --out "$work/f" --quiet
  grep -q 'disk full: cannot write .*energy.csv' "$work/run_full.err" || fail "run: no message"
  [ ! -e "$work/f/energy.csv" ] || fail "run: a truncated energy.csv was committed"
  [ -z "$(find "$work/f" -name '*.tmp')" ] || fail "run: .tmp files left"
  grep -q '"status": "disk_full"' "$work/f/summary.json" || fail "run: summary.json status"
  full export_full out.csv.tmp "$sablier" export "$state" -o "$work/out.csv"
  [ ! -e "$work/out.csv" ] || fail "export: a truncated file was committed"
  if [ "$render" = 1 ]; then
    full render_full out.png.tmp "$sablier" render "$state" -o "$work/out.png"
    [ ! -e "$work/out.png" ] || fail "render: a truncated figure was committed"
  fi
fi
echo "cli.output_files: ok"
