#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check.sh SABLIER CASE RANKS WORK RENDER WITH_MPI: runs golden case CASE (tests/golden/cases.sh)
# under `mpirun -n RANKS` into WORK/CASE and compares its outputs with tests/golden/CASE, which
# `--jobs 1` and `--jobs 2` reproduce (golden.CASE): tables, member CSV/JSON, checkpoints byte for
# byte (compare.sh). Exit 77 (skipped) when sablier was built without MPI (WITH_MPI OFF) or with
# the sanitizers (WITH_MPI SANITIZE), or when mpirun is missing.
set -uo pipefail
sablier=$1 case=$2 ranks=$3 work=$4 render=$5 with_mpi=$6
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
golden=$here/../golden
case ${with_mpi^^} in ON | 1 | TRUE | YES) ;;
SANITIZE)
  echo "mpi: skipped under AddressSanitizer: OpenMPI keeps allocations past MPI_Finalize and its"
  echo "memory hooks are not made for ASan (the Release builds run this test)"
  exit 77 ;;
*)
  echo "mpi: skipped: sablier was built without MPI (SABLIER_WITH_MPI=OFF)"
  exit 77 ;;
esac
command -v mpirun >/dev/null || { echo "mpi: skipped: no mpirun on PATH"; exit 77; }
. "$golden/cases.sh"
mkdir -p "$work" || exit 2
work=$(cd "$work" && pwd)
out=$work/$case
rm -rf "$out"
# golden_run calls its BIN with sablier's arguments: BIN is mpirun around this build's sablier
# (as root in CI: --allow-run-as-root; more ranks than cores: --oversubscribe)
wrapper=$work/$case.mpirun
printf '#!/bin/sh\nexec mpirun --allow-run-as-root --oversubscribe -n %s "%s" "$@"\n' \
  "$ranks" "$sablier" >"$wrapper"
chmod +x "$wrapper"
golden_run "$case" "$wrapper" "$out" </dev/null >"$out.log" 2>&1
rc=$?
if [ $rc -ne 0 ]; then
  cat "$out.log" >&2
  echo "mpi: FAIL: case $case under mpirun -n $ranks exited with status $rc ($out.log)" >&2
  exit 1
fi
exec bash "$golden/compare.sh" "$golden/$case" "$out" "$render" "$sablier"
