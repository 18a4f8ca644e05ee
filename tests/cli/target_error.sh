#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.check_target_error: `sablier check SCENE --target-error E` prints numbers that agree with
# each other: C / n^p = E (n not capped), t_c / n = dt, cost = ns x grains / dt; the event onset
# needs fewer steps; a bad E is a usage error.
set -u
sablier=$1 tiny=$2
fail() { echo "cli.check_target_error: $*" >&2; exit 1; }
for onset in step event; do
  out=$("$sablier" check "$tiny" --set species.0.gamma_n=50 --set contact.onset=\"$onset\" \
    --target-error 1e-3 2>&1) || fail "check failed: $out"
  echo "$out" | grep -q "^dt advice for |e - e_n| <= 0.001 (velocity_verlet, onset $onset):" ||
    fail "no advice header for onset $onset: $out"
  echo "$out" | awk -v onset="$onset" '
    /^  stiffest pair/ { tc = $4; e = $7 }
    /^  law/ { c = $4; split($6, a, "^"); p = a[2] }
    /^  steps per contact/ { n = $4; capped = /raised/ }
    /^  time step/ { dt = $3 }
    /^  cost/ { cost = $2; ns = $9; grains = $14 }
    function rel(a, b) { d = a - b; if (d < 0) d = -d; return d / (b < 0 ? -b : b) }
    END {
      bad = ""
      if (!(tc > 0 && e > 0 && e < 1 && c > 0 && p > 0 && n > 0 && dt > 0 && cost > 0 && ns > 0))
        bad = bad " missing numbers"
      if (!capped && rel(c / n ^ p, 1e-3) > 1e-4) bad = bad " C/n^p != E"
      if (rel(tc / n, dt) > 1e-4) bad = bad " t_c/n != dt"
      if (rel(ns * 1e-9 * grains / dt, cost) > 1e-4) bad = bad " cost != ns x grains / dt"
      if (onset == "event" && p < 1.8) bad = bad " event order < 1.8"
      if (bad != "") { print "onset " onset ":" bad > "/dev/stderr"; exit 1 }
      print n
    }' >"${TMPDIR:-/tmp}/target_error_$onset.$$" || fail "inconsistent advice: $out"
done
n_step=$(cat "${TMPDIR:-/tmp}/target_error_step.$$") n_event=$(cat "${TMPDIR:-/tmp}/target_error_event.$$")
rm -f "${TMPDIR:-/tmp}/target_error_step.$$" "${TMPDIR:-/tmp}/target_error_event.$$"
awk -v a="$n_step" -v b="$n_event" 'BEGIN { exit !(b * 5 < a) }' ||
  fail "event onset n $n_event is not well below step onset n $n_step"
"$sablier" check "$tiny" --target-error 0.7 >/dev/null 2>&1
[ $? = 2 ] || fail "--target-error 0.7 not refused with status 2"
echo "cli.check_target_error: ok (n $n_step step, $n_event event)"
