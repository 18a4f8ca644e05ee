#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.manifest_sandbox: the output folder is a sandbox. manifest.txt lists only what
# the run itself wrote (a user's file, or the scene, modified during or after the run's start is
# not listed), so the next run into the folder never deletes them, even with `--out .`; and the
# cleanup of a previous run's files follows no link out of the folder and removes nothing but
# regular files inside it.
set -u
sablier=$1 tiny=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.manifest_sandbox: $*" >&2; exit 1; }
run() { # run FOLDER ARGS...: a run that must succeed
  local dir=$1
  shift
  (cd "$dir" && "$sablier" run "$@" --quiet) >"$work/run.log" 2>&1 || fail "run: $(cat "$work/run.log")"
}
# --out . with the scene and a user's notes in the folder, both touched after the run starts
mkdir -p "$work/dot"
cp "$tiny" "$work/dot/tiny.scene"
echo "mine" >"$work/dot/notes.txt"
touch -d '+1 hour' "$work/dot/tiny.scene" "$work/dot/notes.txt"
run "$work/dot" tiny.scene --out .
m="$work/dot/manifest.txt"
for own in energy.csv summary.json scene.resolved.cfg; do
  grep -qx "$own" "$m" || fail "the manifest misses the run's $own: $(cat "$m")"
done
grep -q "tiny.scene\|notes.txt" "$m" && fail "the manifest lists the user's files: $(cat "$m")"
run "$work/dot" tiny.scene --out .
[ -f "$work/dot/tiny.scene" ] || fail "the second run deleted the scene"
[ -f "$work/dot/notes.txt" ] || fail "the second run deleted the user's notes.txt"
# a manifest that names a file through a link to a folder outside, a link and a FIFO
mkdir -p "$work/outside"
echo "victim" >"$work/outside/victim.txt"
run "$work" "$tiny" --out out
ln -s ../outside "$work/out/away"
ln -s ../outside/victim.txt "$work/out/victim_link"
mkfifo "$work/out/pipe"
printf 'away/victim.txt\nvictim_link\npipe\n../outside/victim.txt\n' >>"$work/out/manifest.txt"
run "$work" "$tiny" --out out
[ -f "$work/outside/victim.txt" ] || fail "the cleanup followed a link out of the folder"
[ -L "$work/out/victim_link" ] || fail "the cleanup removed a listed link"
[ -p "$work/out/pipe" ] || fail "the cleanup removed a listed FIFO"
grep -q "away\|victim_link\|pipe" "$work/out/manifest.txt" && fail "the new manifest lists them"
echo "cli.manifest_sandbox: ok"
