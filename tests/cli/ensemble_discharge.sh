#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.ensemble_discharge: `sablier ensemble` reaches the discharge protocol (thesis 004), whose
# time step is its own (discharge.dt_divisor): members are `sablier discharge` runs with
# discharge.dt_divisor = 0 and the listed time step (AppExperiment.member).
# Checked: every member's summary.json has the level's dt, a member's s and h are those of the
# same `sablier discharge` run by hand, --steps-per-contact halves dt when n doubles, a dt above
# the protocol's stability limit is refused with nothing made, and dt_divisor = 0.5 is refused.
set -u
sablier=$1 scene=$2 work=$3
fail() { echo "cli.ensemble_discharge: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
small=(--set discharge.base_length=10 --set 'discharge.widths=[2.2]')
"$sablier" ensemble "$scene" --dt 0.002,0.001 --seeds 3 --jobs 2 "${small[@]}" \
  --observe discharges.0.s,discharges.0.h --out "$work/e" --quiet >"$work/e.stdout" \
  2>"$work/e.stderr" || fail "ensemble failed ($?): $(cat "$work/e.stderr")"
[ "$(wc -l <"$work/e/members.csv")" = 7 ] || fail "members.csv: expected 6 members"
awk -F, 'NR > 1 && $4 != 0 { exit 1 }' "$work/e/members.csv" || fail "a member failed"
for dt in 0.002 0.001; do
  for seed in 1 2 3; do
    m=$work/e/dt=$dt/seed-$seed
    grep -q "^  \"dt\": $dt,$" "$m/summary.json" ||
      fail "$m: the protocol's dt is not the level's: $(grep '"dt"' "$m/summary.json")"
    grep -q "^  \"seed\": $seed,$" "$m/summary.json" || fail "$m: seed not $seed"
  done
done
grep -q '^discharges.0.s: ' "$work/e.stdout" || fail "no answer for s: $(cat "$work/e.stdout")"
grep -q '^discharges.0.h: ' "$work/e.stdout" || fail "no answer for h: $(cat "$work/e.stdout")"
# a member is the same run as `sablier discharge` by hand
"$sablier" discharge "$scene" --out "$work/hand" --quiet --seed 2 "${small[@]}" \
  --set discharge.dt_divisor=0 --set time.dt=0.001 >/dev/null 2>&1 || fail "discharge by hand"
row=$(awk -F, '$1 == "0.001" && $3 == 2 { print $6 "," $7 }' "$work/e/members.csv")
hand=$(awk -F, 'NR == 2 { print $4 "," $6 }' "$work/hand/discharge.csv")
[ -n "$row" ] && [ "$row" = "$hand" ] || fail "member s,h '$row' != discharge by hand '$hand'"
# without dt_divisor = 0 the protocol keeps the thesis's dt = sqrt(m_min/k_n)/50
"$sablier" discharge "$scene" --out "$work/thesis" --quiet "${small[@]}" --set time.dt=0.001 \
  >/dev/null 2>&1 || fail "discharge with the thesis's dt"
grep -q '^  "dt": 0.001,$' "$work/thesis/summary.json" && fail "dt_divisor = 50 took time.dt"
# --steps-per-contact: n twice as large, dt half as large
"$sablier" ensemble "$scene" --steps-per-contact 300,600 --seeds 2 "${small[@]}" \
  --observe discharges.0.s --out "$work/spc" --quiet >/dev/null 2>"$work/spc.stderr" ||
  fail "--steps-per-contact: $(cat "$work/spc.stderr")"
awk -F, 'NR == 2 { d1 = $2; n1 = $3 } NR == 3 { d2 = $2; n2 = $3 }
  END { r = d2 / d1; exit !(n1 == 600 && n2 == 300 && r > 1.9999 && r < 2.0001) }' \
  "$work/spc/ensemble.csv" || fail "--steps-per-contact rows: $(cat "$work/spc/ensemble.csv")"
# above the stability limit: exit 2, nothing made
"$sablier" ensemble "$scene" --dt 1,0.5 "${small[@]}" --observe discharges.0.s --out "$work/bad" \
  >/dev/null 2>"$work/bad.stderr"
rc=$?
[ $rc = 2 ] || fail "unstable dt: exit $rc, expected 2"
grep -q "ensemble: --dt 1: .*dt_divisor\` = 0 takes the scene's time step, 1 s, which is not in (0," \
  "$work/bad.stderr" || fail "unstable dt: $(cat "$work/bad.stderr")"
[ ! -e "$work/bad" ] || fail "unstable dt: $work/bad was made"
"$sablier" discharge "$scene" --out "$work/div" --set discharge.dt_divisor=0.5 >/dev/null \
  2>"$work/div.stderr"
rc=$?
[ $rc = 2 ] || fail "dt_divisor 0.5: exit $rc"
grep -q "dt_divisor.* must be >= 1, or 0" "$work/div.stderr" || fail "dt_divisor: $(cat "$work/div.stderr")"
"$sablier" discharge "$scene" --out "$work/big" --set discharge.dt_divisor=0 --set time.dt=1 \
  >/dev/null 2>"$work/big.stderr"
rc=$?
[ $rc = 2 ] && [ ! -e "$work/big" ] || fail "discharge with dt above the limit: exit $rc"
grep -q "^--set discharge.dt_divisor: \`dt_divisor\` = 0 takes the scene's time step, 1 s," \
  "$work/big.stderr" || fail "dt above the limit: $(cat "$work/big.stderr")"
# the same in the scene file: its line, refused by the loader for every command (check, study)
sed -e 's/^time = { dt = 6e-4;/time = { dt = 1.0;/' \
  -e 's/^  base_length = 25.0; .*/&\n  dt_divisor = 0;/' "$scene" >"$work/unstable.scene"
line=$(grep -n '^  dt_divisor = 0;' "$work/unstable.scene" | cut -d: -f1)
for cmd in check discharge study; do
  args=(); [ $cmd = check ] || args=(--out "$work/u-$cmd")
  "$sablier" $cmd "$work/unstable.scene" "${args[@]}" >/dev/null 2>"$work/u.stderr"
  rc=$?
  [ $rc = 2 ] && [ ! -e "$work/u-$cmd" ] || fail "$cmd of the unstable scene: exit $rc"
  grep -q "unstable.scene:$line: discharge: \`dt_divisor\` = 0 takes the scene's time step, 1 s" \
    "$work/u.stderr" || fail "$cmd, unstable scene: $(cat "$work/u.stderr")"
done
echo "cli.ensemble_discharge: ok"
