#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.remove_ids_missing: a stage whose grains come from a state file (so its ids are known only as
# it starts; ids of the scene's own grains are checked at load, cli.bad.remove_ids_unknown) and
# whose remove_ids names no grain of that world is an error (exit 2, the id named, summary.json
# "error"), not ignored; ids that exist are removed.
set -u
sablier=$1 base=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.remove_ids_missing: $*" >&2; exit 1; }
"$sablier" run "$base" --out "$work/fall" --quiet --set time.end=0.01 2>"$work/err.txt" ||
  fail "the first run failed: $(cat "$work/err.txt")"
cp "$work/fall/run.state" "$work/fall.state"
write_scene() { # IDS
  sed '/^time = {/,/^};/d' "$base" >"$work/s.scene"
  cat >>"$work/s.scene" <<SCENE
time = { dt = 1e-5; end = 0.01; };
stages = ( { name = "cut"; load = "fall.state"; remove_ids = [$1]; } );
SCENE
}
write_scene "0, 7"
"$sablier" run "$work/s.scene" --out "$work/bad" --quiet 2>"$work/err.txt"
rc=$?
[ "$rc" = 2 ] || fail "exit $rc, expected 2: $(cat "$work/err.txt")"
grep -q "stage cut: remove_ids: 1 of its 2 ids name no grain of the world (first: 7" "$work/err.txt" ||
  fail "stderr: $(cat "$work/err.txt")"
grep -q '"status": "error"' "$work/bad/summary.json" || fail "summary.json does not say error"
write_scene "0"
"$sablier" run "$work/s.scene" --out "$work/good" --quiet 2>"$work/err.txt" ||
  fail "an existing id refused: $(cat "$work/err.txt")"
grep -q '"removed": 1' "$work/good/summary.json" || fail "grain 0 not removed: $(grep removed "$work/good/summary.json")"
echo "cli.remove_ids_missing: ok"
