#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.sediment_alias: the sediment family's group is `sediment`, and `fluid`, its older name, is
# still accepted: `sablier sediment` sets the Shields number of each member under the name the
# scene uses (a member of a `fluid` scene got `sediment.shields` too and was refused for giving
# the group twice), and a scene that gives both names is refused before anything runs.
set -u
sablier=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.sediment_alias: $*" >&2; exit 1; }

sed 's/^sediment = {/fluid = {/' "$scene" >"$work/old.scene"
grep -q '^fluid = {' "$work/old.scene" || fail "$scene has no \`sediment = {\` line"
short=(--shields 0.1 --jobs 1 --quiet --set stages.settle.time.end=0.2
       --set stages.flow.time.end=0.2)
for name in sediment fluid; do
  input=$scene
  [ "$name" = fluid ] && input=$work/old.scene
  "$sablier" sediment "$input" --out "$work/$name" "${short[@]}" 2>"$work/$name.err" ||
    fail "sediment on a \`$name\` scene: exit $?: $(cat "$work/$name.err")"
  grep -q '"shields": 0.1,' "$work/$name/shields=0.1/sediment.json" ||
    fail "the member of a \`$name\` scene did not run at Theta = 0.1 (the scene's is 0.8)"
  [ -s "$work/$name/flux.csv" ] || fail "no flux.csv for a \`$name\` scene"
done

"$sablier" check "$scene" --set fluid.shields=0.1 >/dev/null 2>"$work/both.err"
rc=$?
[ "$rc" = 2 ] || fail "a scene with \`sediment\` and \`fluid\`: exit $rc, expected 2"
grep -q '`fluid` is an older name of `sediment`: keep one' "$work/both.err" ||
  fail "a scene with both names: $(cat "$work/both.err")"
exit 0
