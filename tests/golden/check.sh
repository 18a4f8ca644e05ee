#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check.sh SABLIER CASE WORK RENDER: runs golden case CASE with SABLIER into WORK/CASE (from the
# repository root) and compares its outputs with tests/golden/CASE (compare.sh).
set -uo pipefail
sablier=$1 case=$2 work=$3 render=$4
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
. "$here/cases.sh"
mkdir -p "$work" || exit 2
out=$(cd "$work" && pwd)/$case
rm -rf "$out"
golden_run "$case" "$sablier" "$out" >"$out.log" 2>&1
rc=$?
if [ $rc -ne 0 ]; then
  cat "$out.log" >&2
  echo "golden: FAIL: case $case exited with status $rc (log above, $out.log)" >&2
  exit 1
fi
exec bash "$here/compare.sh" "$here/$case" "$out" "$render" "$sablier"
