#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The ABI check of a public shared library (docs/install.md, "ABI"; ctest abi.*).
#
#   tests/install/abi.sh LIBRARY RECORD                  check
#   tests/install/abi.sh LIBRARY RECORD --update VERSION record (new symbols: since VERSION)
#
# RECORD is a Debian symbols file (deb-symbols(5)), the one the package libsablier-...V ships:
# its first line names the SONAME, each further line one exported symbol and the version that
# brought it. Fails (status 1) when a recorded symbol is no longer exported and the SONAME is
# the recorded one: a removed symbol needs a new SONAME (the next 0.x minor, cmake/abi.cmake).
# With another SONAME the record is out of date: it says so and passes (the removal is allowed),
# and `--update` records the new list. Symbols not recorded yet are listed, and pass.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: abi.sh LIBRARY RECORD [--update VERSION]" >&2; exit 2; }
lib=$1
record=$2
[ -f "$lib" ] || { echo "abi.sh: no library $lib" >&2; exit 2; }
soname=$(readelf -d "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ -n "$soname" ] || { echo "abi.sh: $lib has no SONAME" >&2; exit 2; }
# the exported (defined, global or weak) dynamic symbols, without their version
exported=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[A-Z]$/ {sub(/@.*/, "", $3); print $3}' | sort -u)

if [ "${3:-}" = --update ]; then
  version=${4:?abi.sh: --update needs the VERSION that brings the new symbols}
  # the package name of the SONAME (Debian policy 8.1: libfoo.so.0.1 -> libfoo0.1)
  package=$(sed -E 's/([0-9])\.so\./\1-/; s/\.so(\.|$)//' <<<"$soname")
  {
    echo "$soname $package #MINVER#"
    while read -r name; do
      since=$(awk -v n="$name@Base" '$1 == n {print $2}' "$record" 2>/dev/null || true)
      echo " $name@Base ${since:-$version}"
    done <<<"$exported"
  } >"$record.tmp"
  mv "$record.tmp" "$record"
  echo "abi: recorded $(wc -l <<<"$exported") symbols of $soname in $record"
  exit 0
fi

[ -f "$record" ] || { echo "abi.sh: no record $record (abi.sh $lib $record --update VERSION)" >&2; exit 2; }
recorded_soname=$(head -1 "$record" | awk '{print $1}')
recorded=$(sed -n 's/^ \([^@ ]*\)@.*/\1/p' "$record" | sort -u)
removed=$(comm -23 <(echo "$recorded") <(echo "$exported"))
added=$(comm -13 <(echo "$recorded") <(echo "$exported"))
if [ "$soname" != "$recorded_soname" ]; then
  echo "abi: $lib is $soname, the record $record is for $recorded_soname:" \
       "$(grep -c . <<<"$removed" || true) symbols removed with the SONAME change (allowed);" \
       "record the new ABI with --update"
  exit 0
fi
if [ -n "$added" ]; then
  echo "abi: $(wc -l <<<"$added") exported symbols of $soname not recorded yet (--update records them):"
  sed 's/^/  + /' <<<"$added"
fi
if [ -n "$removed" ]; then
  echo "abi: $soname no longer exports $(wc -l <<<"$removed") recorded symbols, and its SONAME" \
       "did not change (a removal needs the next SONAME, cmake/abi.cmake):" >&2
  sed 's/^/  - /' <<<"$removed" >&2
  exit 1
fi
echo "abi: $soname exports all $(wc -l <<<"$recorded") recorded symbols of $record"
