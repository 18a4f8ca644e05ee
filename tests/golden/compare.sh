#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# compare.sh GOLDEN_DIR NEW_DIR RENDER SABLIER
# Compares a fresh output folder with the recorded one (tests/golden/README.md):
# - every CSV / JSON (and the study's header-less samples/*.csv, *.dep, *.map) field by field,
#   textually (results are bit-identical), timing fields and the output folder excepted
#   (flatten.awk);
# - every PNG through `SABLIER diff GOLDEN NEW --threshold 0 --shift 0` when RENDER is ON;
#   with RENDER OFF the PNGs are neither compared nor required;
# - a plot's data beside it (a CSV beginning "# sablier plot data", docs/figures.md#plot-data)
#   byte for byte, like its plot only when RENDER is ON;
# - every *.state checkpoint byte for byte against GOLDEN_DIR/states.sha256;
# - a recorded file missing from the new output, or a new file of these kinds that is not in
#   the golden set, fails. Movies (.mp4), logs (.txt) are not compared; a leftover .tmp fails.
set -uo pipefail
golden=$1 new=$2 render=$3 sablier=$4
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
case ${render^^} in ON|1|TRUE|YES) render=1 ;; *) render=0 ;; esac
new_abs=$(cd "$new" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "golden: FAIL: $*" >&2; failures=$((failures + 1)); }

kind_of() { # kind_of REL DIR
  case $1 in
    *.csv) if [ "$(head -c 19 "$2/$1" 2>/dev/null)" = "# sablier plot data" ]; then echo plotcsv; return; fi ;;
  esac
  case $1 in
    *.png) echo png ;;
    *.json) echo json ;;
    samples/*.csv | */samples/*.csv | *.dep | *.map) echo headerless ;;
    *.csv) echo csv ;;
    *.state) echo state ;;
    *.tmp) echo tmp ;;
    *) echo other ;;
  esac
}
list() { (cd "$1" && find . -type f | sed 's|^\./||' | LC_ALL=C sort); }

compared=0 pngs=0
list "$golden" | grep -v '^states\.sha256$' >"$tmp/golden.list"
list "$new" >"$tmp/new.list"

# files of the new output that the golden set lacks
while IFS= read -r rel; do
  kind=$(kind_of "$rel" "$new")
  case $kind in
    tmp) fail "$new/$rel: an output left under its temporary name" ;;
    png | plotcsv) [ $render = 1 ] && ! grep -qxF "$rel" "$tmp/golden.list" &&
           fail "$rel: new output file, not in the golden set $golden" ;;
    csv | json | headerless)
      grep -qxF "$rel" "$tmp/golden.list" || fail "$rel: new output file, not in the golden set $golden" ;;
  esac
done <"$tmp/new.list"

while IFS= read -r rel; do
  kind=$(kind_of "$rel" "$golden")
  g=$golden/$rel n=$new/$rel
  if [ $kind = plotcsv ]; then
    [ $render = 1 ] || continue
    if [ ! -f "$n" ]; then fail "$rel: missing from the new output $new"; continue; fi
    compared=$((compared + 1))
    cmp -s "$g" "$n" || fail "$rel differs from $g (diff $g $n)"
    continue
  fi
  if [ $kind = png ]; then
    [ $render = 1 ] || continue
    if [ ! -f "$n" ]; then fail "$rel: missing from the new output $new"; continue; fi
    pngs=$((pngs + 1))
    if ! result=$("$sablier" diff "$g" "$n" --threshold 0 --shift 0 2>&1); then
      fail "$rel: images differ (sablier diff $g $n --threshold 0 --shift 0): $result"
    fi
    continue
  fi
  if [ ! -f "$n" ]; then fail "$rel: missing from the new output $new"; continue; fi
  case $kind in
    csv | json | headerless) ;;
    *) fail "$rel: recorded file of a kind that is not compared"; continue ;;
  esac
  compared=$((compared + 1))
  awk -v mode=$kind -v rel="$rel" -v out="" -f "$here/flatten.awk" "$g" >"$tmp/g.flat"
  awk -v mode=$kind -v rel="$rel" -v out="$new_abs" -f "$here/flatten.awk" "$n" >"$tmp/n.flat"
  if ! cmp -s "$tmp/g.flat" "$tmp/n.flat"; then
    awk -F'\t' -v gf="$tmp/g.flat" -v nf="$tmp/n.flat" -v rel="$rel" '
      BEGIN {
        while ((getline a < gf) > 0) g[++ng] = a
        while ((getline b < nf) > 0) n[++nn] = b
        m = ng > nn ? ng : nn; shown = 0; bad = 0
        for (i = 1; i <= m; ++i) {
          if (i <= ng && i <= nn && g[i] == n[i]) continue
          ++bad
          if (shown >= 10) continue
          ++shown
          if (i > ng) { split(n[i], y, "\t"); printf "  %s:%d: field %s: not in the golden file, new `%s`\n", rel, y[1], y[2], y[3]; continue }
          if (i > nn) { split(g[i], x, "\t"); printf "  %s:%d: field %s: golden `%s`, missing from the new file\n", rel, x[1], x[2], x[3]; continue }
          split(g[i], x, "\t"); split(n[i], y, "\t")
          where = (x[1] == y[1]) ? x[1] : x[1] " (new line " y[1] ")"
          fld = (x[2] == y[2]) ? x[2] : x[2] " (new field " y[2] ")"
          printf "  %s:%s: field %s: golden `%s`, new `%s`\n", rel, where, fld, x[3], y[3]
        }
        if (bad > shown) printf "  ... and %d more differing fields\n", bad - shown
        if (ng != nn) printf "  %s: %d fields recorded, %d in the new file\n", rel, ng, nn
      }' >"$tmp/report" </dev/null
    fail "$rel differs from $g:"
    cat "$tmp/report" >&2
  fi
done <"$tmp/golden.list"

# checkpoints, byte for byte
states=0
if [ -f "$golden/states.sha256" ]; then
  (cd "$new" && find . -type f -name '*.state' | sed 's|^\./||' | LC_ALL=C sort | xargs -r sha256sum) \
    >"$tmp/states.new"
  while read -r sum rel; do
    states=$((states + 1))
    got=$(awk -v r="$rel" '$2 == r { print $1 }' "$tmp/states.new")
    if [ -z "$got" ]; then fail "$rel: checkpoint missing from the new output $new"
    elif [ "$got" != "$sum" ]; then fail "$rel: checkpoint differs (sha256 $got, recorded $sum)"
    fi
  done <"$golden/states.sha256"
  while read -r sum rel; do
    awk -v r="$rel" '$2 == r { f = 1 } END { exit !f }' "$golden/states.sha256" ||
      fail "$rel: new checkpoint, not in $golden/states.sha256"
  done <"$tmp/states.new"
fi

if [ $failures -gt 0 ]; then
  echo "golden: $golden: $failures failure(s)" >&2
  exit 1
fi
echo "golden: $golden: ok ($compared text files, $pngs images, $states checkpoints)"
