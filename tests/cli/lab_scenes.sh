#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.lab_scenes.CASE: the controlled-boundary scenes of docs/experiments.md load (`sablier
# check`) and a shortened run (--set) shows the physics each is for:
#   biaxial      scenes/compression/biaxial.scene, axial strains up to 3 %: the servo side wall
#                holds its 12000 N within 5 % (time mean; a proportional servo lags a dilating
#                sample) and the sample mobilises sin phi = (s1 - s3) / (s1 + s3) > 0.3
#   janssen      scenes/silo/janssen.scene, 300 grains asked: the walls carry the whole weight
#                (the sum of their loads = the inserted grains' weight within 5 %: random radii)
#                and the base less than 90 % of it (Janssen screening by wall friction)
#   plane_shear  scenes/shear/plane_shear.scene at 1 m/s: the lid holds P = 2000 N/m within 4 %
#                (time mean; the servo lags the dilating layer), mu = F_x / N lies in [0.2, 0.6]
#                and the layer is sheared (the bulk moves faster near the base than the lid)
#   impact       scenes/impact/impact.scene as shipped (a drop of about 1.5 m): the source puts
#                the projectile in, and it ends at rest with its bottom below the bed's surface
set -u
sablier=$1 repo=$2 work=$3 case=$4
fail() { echo "cli.lab_scenes.$case: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
case $case in
biaxial)
  scene=$repo/scenes/compression/biaxial.scene
  sets=(--set stages.compress.time.end=3.0 --set 'output.walls.window=[6.5,9.0]') ;;
janssen)
  scene=$repo/scenes/silo/janssen.scene
  sets=(--set sources.feed.count=300 --set time.end=8.0 --set stages.fill.time.end=8.0
        --set 'output.walls.window=[7.5,8.0]') ;;
plane_shear)
  scene=$repo/scenes/shear/plane_shear.scene
  sets=(--set 'motions.slide.velocity=[1.0,0.0]' --set stages.shear.time.end=6.0
        --set 'output.walls.window=[11.0,14.0]') ;;
impact)
  scene=$repo/scenes/impact/impact.scene
  sets=() ;;
*) fail "unknown case" ;;
esac
"$sablier" check "$scene" >"$work/check.log" 2>&1 || fail "check failed: $(cat "$work/check.log")"
"$sablier" run "$scene" --out "$work/run" --quiet --threads 1 ${sets[@]+"${sets[@]}"} \
  >"$work/run.log" 2>&1 || fail "run failed: $(cat "$work/run.log")"
if [ "$case" = impact ]; then
  for stage in settle impact; do
    "$sablier" export "$work/run/$stage.state" -o "$work/run/$stage.csv" --format csv \
      >/dev/null 2>&1 || fail "export $stage.state failed"
  done
fi
python3 - "$work/run" "$case" <<'PY' || fail "the physics is off (above)"
import csv, json, math, os, sys
run, case = sys.argv[1], sys.argv[2]
if case == "impact":
    def grains(stage):
        return [{k: float(v) for k, v in r.items()}
                for r in csv.DictReader(open(os.path.join(run, stage + ".csv")))]
    bed, end = grains("settle"), grains("impact")
    surface = max(g["y"] + g["r"] for g in bed if abs(g["x"] - 1.5) < 0.5)
    projectile = max(end, key=lambda g: g["r"])
    speed = math.hypot(projectile["vx"], projectile["vy"])
    print("impact: %d grains then %d, projectile r %.2f, bottom %.3f m, surface %.3f m, "
          "speed %.4f m/s" % (len(bed), len(end), projectile["r"], projectile["y"] -
                              projectile["r"], surface, speed))
    assert len(end) == len(bed) + 1 and projectile["r"] == 0.15, projectile
    assert projectile["y"] - projectile["r"] < surface, (projectile, surface)
    assert speed < 0.05, speed
    sys.exit(0)
rows = list(csv.DictReader(open(os.path.join(run, "walls.csv"))))
walls = {}
for r in rows:
    walls.setdefault(int(r["wall"]), []).append({k: (v if k == "stage" else float(v))
                                                 for k, v in r.items()})
summary = json.load(open(os.path.join(run, "summary.json")))["walls"]
t0, t1 = summary["window"]
mean = summary["mean"]
if case == "biaxial":
    pick = [i for i, r in enumerate(walls[0]) if t0 <= r["t"] <= t1]
    s1 = [walls[3][i]["normal"] / (walls[2][i]["x"] - walls[1][i]["x"]) for i in pick]
    s3 = [walls[2][i]["normal"] / (walls[3][i]["y"] - walls[0][i]["y"]) for i in pick]
    ratio = (sum(s1) - sum(s3)) / (sum(s1) + sum(s3))
    side = mean[2]["normal"]
    print("biaxial: side wall %.0f N (target 12000), sin phi %.3f" % (side, ratio))
    assert abs(side - 12000.0) < 0.05 * 12000.0, side
    assert ratio > 0.3, ratio
elif case == "janssen":
    base = -mean[0]["fy"]
    weight = -sum(m["fy"] for m in mean)
    count = json.load(open(os.path.join(run, "summary.json")))["sources"][0]["inserted"]
    assert count >= 280, count
    # the mean mass of a disk of r uniform in [0.04, 0.06] m
    nominal = count * 1000.0 * math.pi * (0.05 ** 2 + 0.02 ** 2 / 12.0) * 9.806
    print("janssen: weight %.0f N (nominal %.0f), base %.0f N (%.3f)" %
          (weight, nominal, base, base / weight))
    assert abs(weight - nominal) < 0.05 * nominal, (weight, nominal)
    assert base < 0.9 * weight, (base, weight)
elif case == "plane_shear":
    lid = mean[0]
    mu = lid["fx"] / lid["normal"]
    prof = list(csv.DictReader(open(os.path.join(run, "profile.csv"))))
    top = 2.45 - lid["offset"]
    def vx(y0, y1):
        v = [float(r["vx"]) for r in prof if float(r["t"]) >= t0 and y0 <= float(r["y"]) <= y1]
        return sum(v) / len(v)
    low, high = vx(0.2, 0.45), vx(top - 0.45, top - 0.2)
    print("plane_shear: P %.0f N/m, mu %.3f, vx %.3f near the base, %.3f near the lid" %
          (lid["stress"], mu, low, high))
    assert abs(lid["stress"] - 2000.0) < 0.04 * 2000.0, lid
    assert 0.2 < mu < 0.6, mu
    assert low > high + 0.05, (low, high)
PY
echo "cli.lab_scenes.$case: ok"
