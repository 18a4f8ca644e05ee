#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.sweep_inputs: the sweep driver refuses bad inputs before anything runs (exit 2, no output
# folder): a --from checkpoint that does not exist or is not a state, a --vary list with more
# values than a key takes, a sweep-file member whose --set is wrong (reported at its line); a long
# --vary list within the bound is kept whole (it was cut at 256 characters), and each member is
# started on one thread when members run side by side (on `auto`'s threads with --jobs 1).
set -u
sablier=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "cli.sweep_inputs: $*" >&2; exit 1; }

# expect RC REGEX OUTDIR -- ARGS...: exit status, stderr, and no output folder
expect() {
  local rc=$1 regex=$2 out=$3; shift 4
  "$sablier" sweep "$@" --out "$out" >"$work/out.txt" 2>"$work/err.txt"
  local got=$?
  [ "$got" = "$rc" ] || fail "sweep $*: exit $got, expected $rc: $(cat "$work/err.txt")"
  grep -Eq -e "$regex" "$work/err.txt" || fail "sweep $*: stderr does not match '$regex': $(cat "$work/err.txt")"
  [ ! -e "$out" ] || fail "sweep $*: created $out"
}

expect 2 "--from: cannot read checkpoint .*/nonexistent/bed.state" "$work/from_missing" -- \
  "$scene" --from "$work/nonexistent/bed.state" --vary species.0.mu=0.3,0.8
echo "not a state" >"$work/text.state"
expect 2 "--from: checkpoint .*text.state.*not a sablier state" "$work/from_text" -- \
  "$scene" --from "$work/text.state" --vary species.0.mu=0.3,0.8

values=$(seq -s, 1 100 | sed 's/\([0-9]*\)/0.\1/g')
expect 2 "at most 32 values per key" "$work/vary_many" -- "$scene" --vary "species.0.mu=$values"

# 30 values, 300+ characters: 30 members, none lost
long=$(for k in $(seq 1 30); do printf '0.%08d,' "$k"; done)
"$sablier" sweep "$scene" --vary "species.0.mu=${long%,}" --dry-run --out "$work/long" \
  >"$work/out.txt" 2>"$work/err.txt" || fail "long --vary list refused: $(cat "$work/err.txt")"
members=$(grep -c "mu=0.000000" "$work/out.txt")
[ "$members" = 30 ] || fail "long --vary list: $members members, expected 30"
# members run side by side, each on one thread (docs/cli.md): every member command says so
one=$(grep "mu=0.000000" "$work/out.txt" | grep -c -e " run .* --threads 1 ")
[ "$one" = 30 ] || fail "dry run: $one of 30 member commands ask for --threads 1"
# one member at a time (--jobs 1): the member takes the threads `auto` gives it
"$sablier" sweep "$scene" --vary species.0.mu=0.3,0.5 --jobs 1 --dry-run --out "$work/jobs1" \
  >"$work/out.txt" 2>"$work/err.txt" || fail "--jobs 1 dry run refused: $(cat "$work/err.txt")"
[ "$(grep -c " run " "$work/out.txt")" = 2 ] && ! grep -q -e "--threads" "$work/out.txt" ||
  fail "--jobs 1 dry run: expected 2 member commands without --threads: $(cat "$work/out.txt")"

cat >"$work/bad.sweep" <<SWEEP
scene = "$scene";
bed_stage = "deposit";
members = (
  { label = "fine"; set = ["species.0.mu=0.5"]; },
  { label = "broken"; set = ["species.0.no_such_key=1"]; }
);
SWEEP
expect 2 "bad.sweep:5: member broken: .*no_such_key" "$work/bad_member" -- "$work/bad.sweep"
echo "cli.sweep_inputs: ok"
