#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# record.sh SABLIER [CASE...]: re-records the golden outputs of the given cases (default all)
# with the binary SABLIER, which must be built with rendering. Run from anywhere; commit the
# result in its own commit that says why (tests/golden/README.md).
set -euo pipefail
sablier=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
shift
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
. "$here/cases.sh"
cd "$here/../.."
[ $# -gt 0 ] || set -- $(golden_cases)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for case in "$@"; do
  out=$work/$case
  echo "golden: recording $case"
  golden_run "$case" "$sablier" "$out" >"$work/$case.log" 2>&1 || {
    cat "$work/$case.log" >&2; echo "golden: $case failed" >&2; exit 1; }
  dest=$here/$case
  rm -rf "$dest"
  mkdir -p "$dest"
  (cd "$out" && find . -type f \( -name '*.csv' -o -name '*.json' -o -name '*.dep' -o -name '*.map' \
      -o -name '*.png' \) | sed 's|^\./||' | LC_ALL=C sort) | while IFS= read -r rel; do
    mkdir -p "$dest/$(dirname "$rel")"
    case $rel in
      *.png) cp "$out/$rel" "$dest/$rel" ;;
      *) sed "s|$out|@OUT@|g" "$out/$rel" >"$dest/$rel" ;;   # the output folder, as compare.sh
    esac
  done
  (cd "$out" && find . -type f -name '*.state' | sed 's|^\./||' | LC_ALL=C sort | xargs -r sha256sum) \
    >"$dest/states.sha256"
  [ -s "$dest/states.sha256" ] || rm -f "$dest/states.sha256"
done
du -sh "$here"
