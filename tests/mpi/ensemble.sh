#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# mpi.ensemble SABLIER SCENE WORK WITH_MPI: `sablier ensemble` under `mpirun -n 3` (2 worker
# ranks) writes the tables and answers of `--jobs 1` (CPU columns aside). Exit 77 (skipped)
# without MPI, under the sanitizers, or without mpirun (as tests/mpi/check.sh).
set -uo pipefail
sablier=$1 scene=$2 work=$3 with_mpi=$4
case ${with_mpi^^} in ON | 1 | TRUE | YES) ;; *) echo "mpi: skipped ($with_mpi)"; exit 77 ;; esac
command -v mpirun >/dev/null || { echo "mpi: skipped: no mpirun on PATH"; exit 77; }
fail() { echo "mpi.ensemble: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
args=(ensemble "$scene" --dt 0.0078125,0.00390625,0.0009765625 --seeds 4 --observe trace.csv:y
  --quiet)
"$sablier" "${args[@]}" --jobs 1 --out "$work/local" >"$work/local.stdout" 2>&1 ||
  fail "--jobs 1: $(cat "$work/local.stdout")"
mpirun --allow-run-as-root --oversubscribe -n 3 "$sablier" "${args[@]}" --out "$work/mpi" \
  >"$work/mpi.stdout" 2>"$work/mpi.stderr" || fail "mpirun: $(cat "$work/mpi.stderr")"
cmp -s <(cut -d, -f1-11 "$work/local/ensemble.csv") <(cut -d, -f1-11 "$work/mpi/ensemble.csv") ||
  fail "ensemble.csv differs under MPI"
cmp -s <(cut -d, -f1-4,6- "$work/local/members.csv") <(cut -d, -f1-4,6- "$work/mpi/members.csv") ||
  fail "members.csv differs under MPI"
cmp -s "$work/local.stdout" "$work/mpi.stdout" || fail "answers differ under MPI"
echo "mpi.ensemble: ok"
