#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check_isa.sh ISA SABLIER CASE WORK RENDER: golden case CASE (check.sh) with the hot loops forced
# to instruction set ISA (SABLIER_ISA, docs/dev/isa.md): every set must write the recorded bits.
# Exit 77 (skipped) when this build or CPU lacks the set (`sablier --version` lists those it runs).
set -uo pipefail
isa=$1
shift
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
runs=$("$1" --version | sed -n 's/^kernels: .*(this CPU:\(.*\))$/\1 /p')
case "$runs" in
*" $isa "*) ;;
*)
  echo "golden: $isa is not among the sets this build and CPU run:$runs (skipped)"
  exit 77
  ;;
esac
chosen=$(SABLIER_ISA=$isa "$1" --version | sed -n 's/^kernels: \([a-z0-9]*\) .*/\1/p')
[ "$chosen" = "$isa" ] || { echo "golden: SABLIER_ISA=$isa chose $chosen" >&2; exit 1; }
SABLIER_ISA=$isa exec bash "$here/check.sh" "$@"
