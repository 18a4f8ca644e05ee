#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest abi.self_test: tests/install/abi.sh fails on a recorded symbol that LIBRARY no longer
# exports while its SONAME stayed, and passes when the SONAME changed with it.
#
#   tests/install/abi_self_test.sh LIBRARY RECORD WORK_DIR
set -euo pipefail
here=$(dirname "$0")
lib=$1
record=$2
work=$3
mkdir -p "$work"
# the record of a library that also exported sim_abi_removed (this one no longer does)
{ cat "$record"; echo " sim_abi_removed@Base 0.1.0"; } >"$work/removed.symbols"
if bash "$here/abi.sh" "$lib" "$work/removed.symbols" 2>"$work/removed.err"; then
  echo "abi.sh passed with a removed symbol and the same SONAME" >&2
  exit 1
fi
grep -q -- '- sim_abi_removed$' "$work/removed.err" || { cat "$work/removed.err" >&2; exit 1; }
echo "abi.sh fails on a removed symbol without a SONAME change:"
sed 's/^/  /' "$work/removed.err"
# the same removal with the SONAME of an older minor recorded: allowed
sed '1s/^\([^ ]*\)\.so\.[0-9.]* /\1.so.0.0 /' "$work/removed.symbols" >"$work/older.symbols"
bash "$here/abi.sh" "$lib" "$work/older.symbols" || { echo "abi.sh failed although the SONAME changed" >&2; exit 1; }
# and the real record passes
bash "$here/abi.sh" "$lib" "$record"
