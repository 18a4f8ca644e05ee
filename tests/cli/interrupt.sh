#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.interrupt: SIGINT/SIGTERM stop a run cleanly (exit 130/143, the running stage's state saved,
# every output committed, summary.json "interrupted", no .tmp left); the next run into the folder
# removes the files the interrupted one listed in its manifest; a folder with another run's
# summary.json and no manifest is refused without --force; summary.json carries the provenance.
# (A full disk: tests/cli/output_files.sh.)
set -u
sablier=$1 scene=$2 tiny=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
fail() { echo "cli.interrupt: $*" >&2; exit 1; }

# Starts a run in the background and sends signal $2 once energy.csv.tmp has grown past a few rows.
interrupt() {
  local out=$1 signal=$2
  "$sablier" run "$scene" --out "$out" --quiet >"$out.log" 2>&1 &
  local pid=$!
  for _ in $(seq 1 600); do
    if [ -f "$out/energy.csv.tmp" ] && [ "$(wc -l <"$out/energy.csv.tmp")" -gt 5 ]; then break; fi
    sleep 0.1
  done
  kill -"$signal" "$pid"
  wait "$pid"
  echo $?
}

rc=$(interrupt "$work/a" INT)
[ "$rc" = 130 ] || fail "SIGINT: exit $rc, expected 130: $(cat "$work/a.log")"
grep -q '"status": "interrupted"' "$work/a/summary.json" || fail "SIGINT: summary.json not interrupted"
grep -q 'interrupted by SIGINT in stage deposit' "$work/a.log" || fail "SIGINT: no message"
[ -s "$work/a/deposit.interrupted.state" ] || fail "SIGINT: no deposit.interrupted.state"
if ! "$sablier" --version | grep -q "render: not built"; then
  [ -s "$work/a/deposit.mp4" ] || fail "SIGINT: the movie was not finalised"
fi
[ -z "$(find "$work/a" -name '*.tmp')" ] || fail "SIGINT: .tmp files left: $(find "$work/a" -name '*.tmp')"
[ "$(tail -n 1 "$work/a/energy.csv" | cut -d, -f10)" = deposit ] || fail "SIGINT: energy.csv incomplete"
grep -qx 'deposit.interrupted.state' "$work/a/manifest.txt" || fail "manifest lacks the state"
grep -qx 'energy.csv' "$work/a/manifest.txt" || fail "manifest lacks energy.csv"

rc=$(interrupt "$work/b" TERM)
[ "$rc" = 143 ] || fail "SIGTERM: exit $rc, expected 143"
grep -q '"status": "interrupted"' "$work/b/summary.json" || fail "SIGTERM: summary.json not interrupted"

# A complete run into the interrupted folder replaces its files: nothing stale stays.
"$sablier" run "$tiny" --out "$work/a" --quiet --set seed=7 >"$work/c.log" 2>&1 ||
  fail "rerun failed: $(cat "$work/c.log")"
[ ! -e "$work/a/deposit.interrupted.state" ] || fail "stale deposit.interrupted.state kept"
grep -q '"status": "ok"' "$work/a/summary.json" || fail "rerun: summary.json not ok"

# Provenance: the command, the --set, the scene's SHA-256, the resolved copy.
sha=$(sha256sum "$tiny" | cut -d' ' -f1)
grep -q "\"scene_sha256\": \"$sha\"" "$work/a/summary.json" || fail "scene_sha256 is not $sha"
grep -q '"sets": \["seed=7"\]' "$work/a/summary.json" || fail "sets not recorded"
grep -q '"command": \[".*", "run", ' "$work/a/summary.json" || fail "command not recorded"
grep -q '"revision": "' "$work/a/summary.json" || fail "revision not recorded"
grep -q 'seed = 7' "$work/a/scene.resolved.cfg" || fail "scene.resolved.cfg lacks the --set"

# Figures carry the provenance in their PNG Comment (when rendering is built).
{ sed '/^output = {/,$d' "$tiny"
  echo 'output = { figures = ({ name = "fig"; stage = "run"; at = "end"; width = 64; height = 64; }); };'
} >"$work/fig.scene"
sed -i 's/end = 1.0;/end = 0.01;/' "$work/fig.scene"
"$sablier" run "$work/fig.scene" --out "$work/e" --quiet >"$work/e.log" 2>&1 || fail "figure run: $(cat "$work/e.log")"
if [ -f "$work/e/fig.png" ]; then
  grep -aq "scene sha256: $(sha256sum "$work/fig.scene" | cut -d' ' -f1)" "$work/e/fig.png" ||
    fail "fig.png has no provenance comment"
fi

# Another run's outputs without a manifest: refused, then accepted with --force.
mkdir -p "$work/d" && echo '{}' >"$work/d/summary.json"
"$sablier" run "$tiny" --out "$work/d" --quiet >"$work/d.log" 2>&1
rc=$?
[ "$rc" = 2 ] || fail "foreign folder: exit $rc, expected 2"
grep -q 'use --force' "$work/d.log" || fail "foreign folder: no message"
"$sablier" run "$tiny" --out "$work/d" --quiet --force >"$work/d.log" 2>&1 || fail "--force failed"
echo "cli.interrupt: ok"
