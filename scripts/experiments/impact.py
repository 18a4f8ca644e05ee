#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Penetration depth against drop height from scenes/impact/impact.scene.

    /usr/bin/python3 scripts/experiments/impact.py [--sablier build/sablier]
        [--heights 0.25,0.5,1,2,4] [--jobs 2] [--out out/impact-study] [--set KEY=VALUE]

Runs the bed once (the `settle` stage, OUT/bed/), then one member per drop height H that loads
it (`stages.settle.skip`, `stages.impact.load`) with the projectile's source region put so that
the projectile's bottom starts H above the bed's surface (the mean over five columns of
|x - 1.5| < 0.5 m of the highest grain top). The depth is how far the projectile's bottom ends
below that surface, from the final state (the projectile is the largest grain). A fit of
depth = a H^(1/3) (Uehara et al. 2003's scaling with the drop height, for a fixed projectile)
is printed with the numbers. Writes OUT/impact.csv (plot data)."""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from members import export_csv, run_members, top_surface  # noqa: E402
from walls_table import write_curve  # noqa: E402

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE = os.path.join(REPO, "scenes", "impact", "impact.scene")
CENTRE = 1.5  # m: the projectile's x (the source region's middle)
RADIUS = 0.15  # m: the projectile's radius (sources.projectile.radius)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sablier", default=os.path.join(REPO, "build", "sablier"))
    ap.add_argument("--heights", default="0.25,0.5,1,2,4")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="out/impact-study")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE for every run")
    a = ap.parse_args()
    heights = [float(v) for v in a.heights.split(",")]
    os.makedirs(a.out, exist_ok=True)
    bed_dir = os.path.join(a.out, "bed")
    run_members(a.sablier, SCENE, [(bed_dir, ["stages.impact.skip=true"] + a.set)], 1)
    bed = os.path.abspath(os.path.join(bed_dir, "settle.state"))
    surface = top_surface(export_csv(a.sablier, bed, os.path.join(bed_dir, "settle.csv")),
                          CENTRE - 0.5, CENTRE + 0.5, 5)
    members = []
    for h in heights:
        y = surface + h + RADIUS
        region = "[%.6f,%.6f,%.6f,%.6f]" % (CENTRE - 0.01, y, CENTRE + 0.01, y + 0.001)
        members.append((os.path.join(a.out, "h%g" % h),
                        ["stages.settle.skip=true", "stages.impact.load=" + bed,
                         "sources.projectile.region=" + region] + a.set))
    run_members(a.sablier, SCENE, members, a.jobs)
    depth = []
    for out, _ in members:
        grains = export_csv(a.sablier, os.path.join(out, "impact.state"),
                            os.path.join(out, "impact.csv"))
        k = int(np.argmax(grains["r"]))
        if abs(grains["r"][k] - RADIUS) > 1e-9:
            raise SystemExit("%s: no projectile (its source found no room?)" % out)
        depth.append(surface - (grains["y"][k] - grains["r"][k]))
    h, depth = np.array(heights), np.array(depth)
    coef = float(np.sum(depth * h ** (1 / 3)) / np.sum(h ** (2 / 3)))  # least squares a
    write_curve(os.path.join(a.out, "impact.csv"), "impact depth against drop height",
                ["H [m]", "depth [m]", "fit [m]"], [h, depth, coef * h ** (1 / 3)])
    print("bed surface %.3f m" % surface)
    for hh, dd in zip(h, depth):
        print("drop height %5.2f m (%5.1f d)  depth %6.3f m (%5.2f d)  total drop %.3f m" %
              (hh, hh / 0.1, dd, dd / 0.1, hh + dd))
    print("fit depth = a H^(1/3): a = %.3f m^(2/3), rms %.3f m" %
          (coef, math.sqrt(float(np.mean((depth - coef * h ** (1 / 3)) ** 2)))))


if __name__ == "__main__":
    main()
