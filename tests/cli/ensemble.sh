#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.ensemble: `sablier ensemble` end to end on a synthetic case with a known shift
# (ensemble_fall.scene: a free fall, symplectic Euler's height is shifted by -g T (dt - dt_ref)/2,
# velocity Verlet's not at all): the tables' structure, the shift reproduced within its interval
# and significant at the coarse dts, no shift with velocity Verlet, the answer lines, the same
# tables with --jobs 1 and 2 (CPU columns aside), each member started on one thread when two run at
# once (and on `auto`'s threads with --jobs 1), and a refused time step runs nothing.
set -u
sablier=$1 scene=$2 work=$3 render=${4:-ON}
fail() { echo "cli.ensemble: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
dts=0.0078125,0.00390625,0.001953125,0.0009765625
run() { # run OUT ARGS...: the ensemble's stdout in OUT.stdout
  local out=$1
  shift
  "$sablier" ensemble "$scene" --dt $dts --seeds 6 --observe trace.csv:y,energy.csv:e_kin \
    --out "$out" --quiet "$@" >"$out.stdout" 2>"$out.stderr" ||
    fail "ensemble $* failed ($?): $(cat "$out.stderr")"
}
run "$work/se" --jobs 2
se=$work/se
head -1 "$se/ensemble.csv" |
  grep -qx "observable,dt_s,steps_per_contact,n,mean,std,ci95,shift,shift_ci95,welch_dof,within,cpu_s_mean" ||
  fail "ensemble.csv header: $(head -1 "$se/ensemble.csv")"
[ "$(wc -l <"$se/ensemble.csv")" = 9 ] || fail "ensemble.csv: expected 8 rows (2 keys x 4 dts)"
[ "$(wc -l <"$se/members.csv")" = 25 ] || fail "members.csv: expected 24 members"
head -1 "$se/members.csv" | grep -qx "dt_s,steps_per_contact,seed,status,cpu_s,trace.csv:y,energy.csv:e_kin" ||
  fail "members.csv header: $(head -1 "$se/members.csv")"
# every member ran (status 0) with its CPU time, and the seeds moved the grain
awk -F, 'NR > 1 && ($4 != 0 || !($5 > 0)) { bad = 1 } NR > 1 { y[$6] = 1 }
  END { n = 0; for (k in y) ++n; exit bad || n < 6 }' "$se/members.csv" ||
  fail "members.csv: a member failed, has no CPU time, or the seeds gave one height"
# members run side by side, each started on one thread (docs/cli.md; their command lines)
summaries=$(find "$se" -name summary.json | wc -l)
single=$(grep -l '"--quiet", "--threads", "1"' $(find "$se" -name summary.json) | wc -l)
[ "$summaries" = 24 ] && [ "$single" = 24 ] ||
  fail "$single of $summaries member summaries (24 expected) record --threads 1"
# the known shift: rows by dt, finest (the reference) first
awk -F, -v g=9.806 'NR > 1 && $1 == "trace.csv:y" {
    ++k; dt[k] = $2; n[k] = $4; shift[k] = $8; half[k] = $9; within[k] = $11 }
  END {
    if (k != 4) { print "expected 4 rows for trace.csv:y"; exit 1 }
    if (dt[1] != 0.0009765625 || shift[1] != 0 || within[1] != 1) { print "bad reference row"; exit 1 }
    for (i = 2; i <= 4; ++i) {
      exact = -g * (dt[i] - dt[1]) / 2
      d = shift[i] - exact; if (d < 0) d = -d
      if (n[i] != 6) { print "row " i ": n = " n[i]; exit 1 }
      if (d > 2e-7) { print "row " i ": shift " shift[i] " != " exact; exit 1 }
      if (d > half[i]) { print "row " i ": exact shift outside the interval " half[i]; exit 1 }
    }
    # the coarsest dt moves the mean beyond its error, downwards
    if (within[4] != 0 || !(shift[4] < 0)) { print "coarsest dt not a significant drop"; exit 1 }
  }' "$se/ensemble.csv" || fail "known shift not reproduced: $(cat "$se/ensemble.csv")"
# e_kin: symplectic Euler's velocity is exact for a constant force: no shift anywhere
awk -F, 'NR > 1 && $1 == "energy.csv:e_kin" && $11 != 1 { exit 1 }' "$se/ensemble.csv" ||
  fail "e_kin shifted: $(cat "$se/ensemble.csv")"
grep -q '^trace.csv:y: ' "$se.stdout" || fail "no answer line for trace.csv:y: $(cat "$se.stdout")"
grep -q '^energy.csv:e_kin: from dt = 0.0078125 s on .*(every dt of the list)$' "$se.stdout" ||
  fail "e_kin answer: $(cat "$se.stdout")"
grep -q '"within_from_dt_s"' "$se/ensemble.json" || fail "ensemble.json has no answer"
if [ "$render" = ON ]; then
  [ -s "$se/ensemble.png" ] && [ -s "$se/ensemble.pdf" ] || fail "no ensemble.png/.pdf"
  # every axis names its unit (the figure lint, docs/figures.md#figure-lint)
  if command -v pdftotext >/dev/null; then
    python3 "$(dirname "$0")/../lint/figure_lint.py" "$se/ensemble.pdf" ||
      fail "the figure lint complains on ensemble.pdf"
  fi
fi
# the same tables with one job (timing columns aside)
run "$work/se1" --jobs 1
for table in ensemble.csv members.csv; do
  cols=1-11
  [ $table = members.csv ] && cols=1-4,6-
  cmp -s <(cut -d, -f$cols "$se/$table") <(cut -d, -f$cols "$work/se1/$table") ||
    fail "$table differs between --jobs 2 and --jobs 1"
done
cmp -s "$se.stdout" "$work/se1.stdout" || fail "answers differ between --jobs 2 and --jobs 1"
# one member at a time (--jobs 1): no --threads 1, the member takes what `auto` gives it
! grep -l -e '"--threads"' $(find "$work/se1" -name summary.json) >/dev/null ||
  fail "--jobs 1: a member was started with --threads"
# velocity Verlet is exact for a free fall: no shift at any dt
run "$work/vv" --set integrator=velocity_verlet
awk -F, 'NR > 1 && $1 == "trace.csv:y" { d = $8 < 0 ? -$8 : $8; if ($11 != 1 || d > 1e-7) exit 1 }' \
  "$work/vv/ensemble.csv" || fail "velocity Verlet shifted: $(cat "$work/vv/ensemble.csv")"
grep -q '^trace.csv:y: from dt = 0.0078125 s on' "$work/vv.stdout" ||
  fail "velocity Verlet answer: $(cat "$work/vv.stdout")"
# --steps-per-contact: each row's dt is the shortest contact time / n, finest first
"$sablier" ensemble "$scene" --steps-per-contact 100,200 --seeds 2 --observe trace.csv:y \
  --out "$work/spc" --quiet >/dev/null 2>"$work/spc.stderr" || fail "--steps-per-contact: $(cat "$work/spc.stderr")"
awk -F, 'NR == 2 { n1 = $3; d1 = $2 } NR == 3 { n2 = $3; d2 = $2 }
  END { r = d1 * n1 / (d2 * n2); exit !(n1 > 199.99 && n1 < 200.01 && n2 > 99.99 && n2 < 100.01 &&
                                       r > 0.9999 && r < 1.0001) }' "$work/spc/ensemble.csv" ||
  fail "--steps-per-contact rows: $(cat "$work/spc/ensemble.csv")"
[ -d "$work/spc/steps_per_contact=100/seed-2" ] || fail "--steps-per-contact member folders"
# a time step the scene refuses: exit 2, nothing made
"$sablier" ensemble "$scene" --dt 0.001,10 --seeds 2 --observe trace.csv:y --out "$work/bad" \
  >/dev/null 2>"$work/bad.stderr"
rc=$?
[ $rc = 2 ] || fail "refused dt: exit $rc, expected 2"
[ ! -e "$work/bad" ] || fail "refused dt: $work/bad was made"
echo "cli.ensemble: ok"
