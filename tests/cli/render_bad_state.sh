#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.render_bad_state: `sablier render STATE` without --scene refuses a state
# with a NaN position or a radius <= 0 (exit 2, the grain named, by the state loader every reader
# shares), writing no figure.
set -u
sablier=$1 tiny=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "cli.render_bad_state: $*" >&2; exit 1; }
if "$sablier" --version | grep -q "render: not built"; then
  echo "cli.render_bad_state: rendering not built, skipped"
  exit 0
fi
"$sablier" run "$tiny" --out "$work/run" --quiet >"$work/run.log" 2>&1 || fail "run: $(cat "$work/run.log")"
state=$(ls "$work/run"/*.state | head -n 1)
# x of the first grain (offset 176, docs/state-format.md) := NaN; then its radius := -1
cp "$state" "$work/nan.state"
printf '\x00\x00\x00\x00\x00\x00\xf8\x7f' | dd of="$work/nan.state" bs=1 seek=176 conv=notrunc status=none
n=$(od -An -t d4 -j 16 -N 4 "$state" | tr -d ' ')
cp "$state" "$work/radius.state"
printf '\x00\x00\x00\x00\x00\x00\xf0\xbf' |
  dd of="$work/radius.state" bs=1 seek=$((176 + 6 * 8 * n)) conv=notrunc status=none
for bad in nan radius; do
  "$sablier" render "$work/$bad.state" -o "$work/$bad.png" >"$work/$bad.log" 2>&1
  rc=$?
  [ "$rc" = 2 ] || fail "$bad: exit $rc, expected 2: $(cat "$work/$bad.log")"
  grep -Eq "grain 0 has (a non-finite position|a radius -1, not a positive finite)" "$work/$bad.log" ||
    fail "$bad: message: $(cat "$work/$bad.log")"
  [ ! -e "$work/$bad.png" ] || fail "$bad: a figure was written"
done
echo "cli.render_bad_state: ok"
