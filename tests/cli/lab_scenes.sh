#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cli.lab_scenes.CASE: the controlled-boundary scenes of docs/experiments.md load (`sablier
# check`) and a shortened run (--set) shows the physics each is for:
#   biaxial      scenes/compression/biaxial.scene, axial strains up to 3 %: the servo side wall
#                holds sigma_3 = 5000 N/m over the sample's height (`between`; walls.csv's stress
#                is its normal load over the base-to-top distance) within 5 % (time mean; a
#                proportional servo lags a dilating sample) and the sample mobilises
#                sin phi = (s1 - s3) / (s1 + s3) > 0.3
#   janssen      scenes/silo/janssen.scene, 300 grains asked: the walls carry the whole weight
#                (the sum of their loads = the inserted grains' weight within 5 %: random radii)
#                and the base less than 90 % of it (Janssen screening by wall friction)
#   plane_shear  scenes/shear/plane_shear.scene at 1 m/s: the lid holds P = 2000 N/m within 4 %
#                (time mean; the servo lags the dilating layer), mu = F_x / N lies in [0.2, 0.6]
#                and the layer is sheared (the bulk moves faster near the base than the lid)
#   plane_shear_lid  scenes/shear/plane_shear_lid.scene as shipped (12 s of shear): the lid's
#                centre moves in x at the motion's 0.5 m/s (after its ramp, to 1e-6 m) while its
#                servo holds P = 2000 N/m within 1 % over the window [10, 20] s (time mean of
#                walls.csv's stress, taken over the servo's `length`, and summary.json's)
#   impact       scenes/impact/impact.scene as shipped (a drop of about 1.5 m): the source puts
#                the projectile in, and it ends at rest with its bottom below the bed's surface;
#                output.depth: depth.csv's largest depth is summary.json's, reached at its t_max,
#                the depth grows from above the surface to it and then stops (the last 0.5 s
#                within 1 cm, the final depth within 5 cm of the largest and equal to the
#                final state's)
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
plane_shear_lid)
  scene=$repo/scenes/shear/plane_shear_lid.scene
  sets=() ;;
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
    rows = [{k: (v if k == "stage" else float(v)) for k, v in r.items()}
            for r in csv.DictReader(open(os.path.join(run, "depth.csv")))]
    assert list(rows[0]) == ["t (s)", "stage", "depth (m)", "bottom (m)", "x (m)", "surface (m)"]
    depth = json.load(open(os.path.join(run, "summary.json")))["depth"]
    d = [r["depth (m)"] for r in rows]
    t = [r["t (s)"] for r in rows]
    k = d.index(max(d))
    print("depth: %d rows from t = %.2f s, from %.3f m to max %.4f m at %.2f s, final %.4f m; "
          "summary %s" % (len(rows), t[0], d[0], d[k], t[k], d[-1], depth))
    assert all(r["stage"] == "impact" for r in rows) and t[0] == 4.0, rows[0]
    assert depth["species"] == "projectile" and depth["rows"] == len(rows), depth
    assert abs(depth["max"] - max(d)) <= 1e-8 * abs(max(d)), (depth, max(d))
    assert abs(depth["t_max"] - t[k]) < 1e-9, (depth, t[k])
    assert d[0] < 0.0 < d[k], d[:3]  # it starts above the surface, ends below
    assert d[-1] > d[k] - 0.05, (d[-1], d[k])
    bottom = projectile["y"] - projectile["r"]  # the final state's
    assert abs(d[-1] - (depth["surface"] - bottom)) < 1e-6, (d[-1], depth["surface"], bottom)
    late = [x for x, tt in zip(d, t) if tt >= t[-1] - 0.5]
    assert max(late) - min(late) < 0.01, late  # it rocks by a few mm in the settling bed
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
    side = mean[2]["stress"]  # normal / the distance between the base and the top wall
    column = [walls[2][i]["stress"] for i in pick]
    assert max(abs(a - b) for a, b in zip(column, s3)) < 1e-6 * 5000.0, (column[:3], s3[:3])
    print("biaxial: side wall %.0f N/m (target 5000 over the height), sin phi %.3f" % (side, ratio))
    assert abs(side - 5000.0) < 0.05 * 5000.0, side
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
elif case == "plane_shear_lid":
    lid = walls[0]
    moving = [r for r in lid if r["t"] >= 8.5 + 1e-9]
    err = max(abs(r["x"] - (1.0 + 0.5 * (r["t"] - 8.0) - 0.125)) for r in moving)
    pick = [r["stress"] for r in lid if t0 <= r["t"] <= t1]
    mean_stress = sum(pick) / len(pick)
    print("plane_shear_lid: %d rows after the ramp, x off by %.3g m at most; P %.2f N/m "
          "(summary %.2f), offset %.3f m, mu %.3f" % (len(moving), err, mean_stress,
                                                    mean[0]["stress"], mean[0]["offset"],
                                                    mean[0]["fx"] / mean[0]["normal"]))
    assert len(moving) >= 70 and err < 1e-6, err
    assert abs(mean_stress - 2000.0) < 0.01 * 2000.0, mean_stress
    assert abs(mean[0]["stress"] - 2000.0) < 0.01 * 2000.0, mean[0]
    assert mean[0]["offset"] > 0.1, mean[0]
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
