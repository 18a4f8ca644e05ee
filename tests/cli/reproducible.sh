#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.reproducible (docs/figures.md "Reproducible files"): the same scene run
# twice, into two folders at different absolute paths and from two working directories, gives
# PNG, PDF and SVG figures with the same bytes (`sablier diff` says identical), and no output
# file holds either folder's absolute path, the working directory or the scene's folder.
# With SOURCE_DATE_EPOCH set, summary.json and the figures' provenance carry that date.
# reproducible.sh SABLIER SCENE WORK
set -u
fail() { echo "cli.reproducible: $*" >&2; exit 1; }
sablier=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work/cwd1" "$work/cwd2/deeper" || fail "cannot make $work"
work=$(cd "$work" && pwd -P)
one="$work/first/run" two="$work/second/other/run"
(cd "$work/cwd1" && "$sablier" run "$scene" --quiet --out "$one") || fail "first run failed"
(cd "$work/cwd2/deeper" && "$sablier" run "$scene" --quiet --out "$two") || fail "second run failed"
for f in drop.png drop.pdf drop.svg; do
  [ -s "$one/$f" ] || fail "no $f"
  cmp -s "$one/$f" "$two/$f" || fail "$f differs between the two runs"
done
out=$("$sablier" diff "$one" "$two") || fail "sablier diff: exit $?: $out"
echo "$out" | grep -q "3 figures: 3 identical" || fail "sablier diff: $out"
scene_dir=$(cd "$(dirname "$scene")" && pwd -P)
for path in "$one" "$two" "$work" "$scene_dir"; do
  if grep -r -l -a -F "$path" "$one" "$two"; then
    fail "an output file holds the absolute path $path"
  fi
done
grep -q '"command": \["sablier", "run", "reproducible.scene", "--quiet", "--out", "."\]' \
  "$one/summary.json" || fail "summary.json command: $(grep -o '"command": [^]]*]' "$one/summary.json")"
# a date only when asked for, then the one asked for
grep -a -q "date: " "$one/drop.png" && fail "drop.png holds a date"
three="$work/third"
SOURCE_DATE_EPOCH=86400 "$sablier" run "$scene" --quiet --out "$three" || fail "third run failed"
grep -q '"date": "1970-01-02T00:00:00Z"' "$three/summary.json" || fail "summary.json ignores SOURCE_DATE_EPOCH"
grep -a -q "date: 1970-01-02T00:00:00Z" "$three/drop.png" || fail "drop.png ignores SOURCE_DATE_EPOCH"
grep -a -q "Date (19700102000000Z)" "$three/drop.pdf" || fail "drop.pdf ignores SOURCE_DATE_EPOCH"
exit 0
