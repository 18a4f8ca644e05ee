#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.lab_scripts: the analyses of docs/experiments.md run end to end on small studies:
# scripts/experiments/janssen.py on 100 and 400 grains (one seed) writes janssen.csv, the base
# carries a smaller share of a taller fill and the fit gives 0 < K mu_w < 1;
# scripts/experiments/biaxial.py on a biaxial run cut at 14 % axial strain finds a peak above
# the critical state. Needs numpy in Debian's /usr/bin/python3 (skipped, exit 77, without it).
set -u
sablier=$1 repo=$2 work=$3
fail() { echo "cli.lab_scripts: $*" >&2; exit 1; }
py=/usr/bin/python3
"$py" -c "import numpy" 2>/dev/null || { echo "cli.lab_scripts: no numpy, skipped"; exit 77; }
rm -rf "$work"
mkdir -p "$work"
"$py" "$repo/scripts/experiments/janssen.py" --sablier "$sablier" --counts 100,400 --seeds 1 \
  --out "$work/janssen" >"$work/janssen.log" 2>&1 || fail "janssen.py: $(cat "$work/janssen.log")"
[ -f "$work/janssen/janssen.csv" ] || fail "no janssen.csv"
"$py" - "$work/janssen.log" <<'PY' || fail "janssen.py's numbers: $(cat "$work/janssen.log")"
import re, sys
text = open(sys.argv[1]).read()
share = [float(v) for v in re.findall(r"F_base/W ([0-9.]+)  fit", text)]
k_mu = float(re.search(r"K mu_w ([0-9.]+)", text).group(1))
assert len(share) == 2 and share[1] < share[0], share
assert 0.0 < k_mu < 1.0, k_mu
PY
"$sablier" run "$repo/scenes/compression/biaxial.scene" --out "$work/biaxial" --quiet \
  --set stages.compress.time.end=13.5 >"$work/biaxial_run.log" 2>&1 ||
  fail "biaxial run: $(cat "$work/biaxial_run.log")"
"$py" "$repo/scripts/experiments/biaxial.py" "$work/biaxial" --critical 0.08,0.14 \
  >"$work/biaxial.log" 2>&1 || fail "biaxial.py: $(cat "$work/biaxial.log")"
"$py" - "$work/biaxial.log" <<'PY' || fail "biaxial.py's numbers: $(cat "$work/biaxial.log")"
import re, sys
text = open(sys.argv[1]).read()
peak = float(re.search(r"peak: sin phi ([0-9.]+)", text).group(1))
crit = float(re.search(r"critical state .*: sin phi ([0-9.]+)", text).group(1))
assert 0.3 < peak < 0.8 and crit < peak, (peak, crit)
PY
echo "cli.lab_scripts: ok"
