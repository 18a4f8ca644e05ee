#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The figure lint's ctests (tests/lint/figure_lint.py, docs/figures.md#figure-lint):
#   figures.sh fixture FIXTURE EXPECTED...  the lint fails on FIXTURE (a plot of an older release)
#                                           and names each EXPECTED complaint (a grep -F string)
#   figures.sh clean FIXTURE...             the lint passes on each FIXTURE (a case it once got
#                                           wrong: tests/lint/fixtures/README.md)
#   figures.sh figures SABLIER WORK         the reduced gallery (scripts/gallery.sh --reduced --pdf)
#                                           and the measure column's plots, as PDF: the lint is
#                                           clean but for tests/lint/figure_waivers.txt
#   figures.sh scenes SABLIER WORK GROUP    the shipped scenes of GROUP (scene_GROUP below), cut
#                                           short with --set, every figure and plot as PDF: each
#                                           one the scenes declare is there and the lint is clean
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
lint=$here/figure_lint.py
mode=${1:?usage: figures.sh fixture FIXTURE EXPECTED... | clean FIXTURE... | figures SABLIER WORK | scenes SABLIER WORK GROUP}
shift
case "$mode" in
fixture)
  fixture=$1
  shift
  out=$(python3 "$lint" "$fixture")
  rc=$?
  echo "$out"
  [ $rc = 1 ] || { echo "figures.sh: the lint exited $rc on $fixture, expected 1" >&2; exit 1; }
  for expected in "$@"; do
    grep -qF -- "$expected" <<<"$out" || { echo "figures.sh: no complaint '$expected'" >&2; exit 1; }
  done
  echo "figures.sh: the lint fails on $(basename "$fixture") as expected"
  ;;
clean)
  python3 "$lint" "$@" || { echo "figures.sh: the lint complains on $*" >&2; exit 1; }
  echo "figures.sh: the lint passes on $# fixture(s)"
  ;;
scenes)
  sablier=$1 work=$2 group=$3
  if "$sablier" --version | grep -q "render: not built"; then
    echo "figures.sh: rendering not built, skipped"
    exit 0
  fi
  sablier=$(realpath "$sablier")
  rm -rf "$work"
  mkdir -p "$work"
  work=$(realpath "$work")
  cd "$here/../.." || exit 1 # the scenes' paths are relative to the repository root
  # shellcheck source=tests/lint/figure_scenes.sh
  . "$here/figure_scenes.sh"
  "scene_$group" || { echo "figures.sh: a run of group $group failed (logs in $work)" >&2; exit 1; }
  shopt -s nullglob
  pdfs=("$work"/*/*.pdf) # every figure and plot of the runs (not a sweep's members: crater does)
  [ ${#pdfs[@]} -ge 1 ] || { echo "figures.sh: no PDF in $work" >&2; exit 1; }
  python3 "$lint" "${pdfs[@]}"
  ;;
figures)
  sablier=$1 work=$2
  if "$sablier" --version | grep -q "render: not built"; then
    echo "figures.sh: rendering not built, skipped"
    exit 0
  fi
  rm -rf "$work"
  mkdir -p "$work"
  "$here/../../scripts/gallery.sh" --reduced --pdf --sablier "$sablier" "$work/gallery" ||
    { echo "figures.sh: the gallery failed" >&2; exit 1; }
  "$sablier" run "$here/../../scenes/measure/column.scene" --out "$work/column" --quiet \
    --set 'render.plot_format="pdf"' >"$work/column.log" 2>&1 ||
    { cat "$work/column.log" >&2; exit 1; }
  shopt -s nullglob
  pdfs=("$work"/gallery/.runs/*/*.pdf "$work"/column/*.pdf) # every figure and plot of the runs
  [ ${#pdfs[@]} -ge 10 ] || { echo "figures.sh: only ${#pdfs[@]} PDFs: ${pdfs[*]}" >&2; exit 1; }
  python3 "$lint" --waivers "$here/figure_waivers.txt" "${pdfs[@]}"
  ;;
*)
  echo "figures.sh: unknown mode $mode" >&2
  exit 2
  ;;
esac
