#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.motion_clock (docs/scenes.md, stages): a motion keeps its clock across stages. The lid of
# tests/cli/motion_clock.scene, pressed for 1 s, held for 0.5 s and pressed again for 1 s, is at
# y = 0.9 m when stage `again` starts and at 0.8 m when it ends (position continuous); with
# `restart_motions = ["press"]` it starts again from y = 1.0 m and ends at 0.9 m. The side wall,
# enabled in `again` only, starts from its own pose at time 0 either way.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.motion_clock: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
# the lid's (wall 1) and the side wall's (wall 2) centres at the first and last rows of `again`
rows() {
  awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) col[$c] = c; next }
           $2 == "again" && $3 == 1 { if (!first) first = $col["y"]; last = $col["y"] }
           $2 == "again" && $3 == 2 { if (!sfirst) sfirst = $col["x"]; slast = $col["x"] }
           END { printf "%.6f %.6f %.6f %.6f\n", first, last, sfirst, slast }' "$1/walls.csv"
}
"$sablier" run "$scene" --out "$work/keep" --quiet >"$work/keep.log" 2>&1 ||
  fail "run failed: $(cat "$work/keep.log")"
got=$(rows "$work/keep")
[ "$got" = "0.900000 0.800000 3.000000 3.200000" ] ||
  fail "kept clock: lid first/last y, side first/last x = $got, expected 0.9 0.8 3 3.2"
"$sablier" run "$scene" --out "$work/restart" --quiet \
  --set 'stages.again.restart_motions=["press"]' >"$work/restart.log" 2>&1 ||
  fail "run with restart_motions failed: $(cat "$work/restart.log")"
got=$(rows "$work/restart")
[ "$got" = "1.000000 0.900000 3.000000 3.200000" ] ||
  fail "restarted clock: lid first/last y, side first/last x = $got, expected 1 0.9 3 3.2"
# a restart of a motion the stage does not enable is refused with the stage's line
"$sablier" check "$scene" --set 'stages.hold.restart_motions=["press"]' >"$work/bad.log" 2>&1
[ $? = 2 ] || fail "restart of a stopped motion: exit status not 2"
grep -q "restart_motions.*motion \`press\` is not enabled in stage \`hold\`" "$work/bad.log" ||
  fail "restart of a stopped motion: $(cat "$work/bad.log")"
echo "cli.motion_clock: ok"
