#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The stress-strain curve of scenes/compression/biaxial.scene from its walls.csv.

    /usr/bin/python3 scripts/experiments/biaxial.py OUT_DIR [--stage compress] [--bin 0.01]
                                                   [--critical 0.12,0.25]

Walls (the scene's order): 0 base, 1 left, 2 right (servo), 3 top (pushed down). The sample is
W = x_right - x_left wide and H = y_top - y_base high; the walls are frictionless, so
sigma_1 = N_top / W and sigma_3 = N_right / H are principal stresses (force per length). In 2D
the mobilised friction angle phi follows from Mohr's circle, sin phi = (sigma_1 - sigma_3) /
(sigma_1 + sigma_3) (the deviatoric stress ratio q/p with q = (s1 - s3)/2, p = (s1 + s3)/2), and
the axial strain is eps = 1 - H / H0 from the stage's first row. Rows are averaged in strain bins
(`--bin`); the peak is the largest bin below the critical window, the critical state the mean
over `--critical` (a strain range) of the bins' means, with their standard error. Writes
OUT_DIR/stress_strain.csv (plot data) and prints the numbers."""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from walls_table import read_walls, write_curve  # noqa: E402


def curve(walls, stage):
    """Axial strain, volumetric strain and sin phi at every row of the stage."""
    pick = np.array([s == stage for s in walls[0]["stage"]])
    if not pick.any():
        raise SystemExit("no walls.csv row of stage %r" % stage)
    width = walls[2]["x"][pick] - walls[1]["x"][pick]
    height = walls[3]["y"][pick] - walls[0]["y"][pick]
    s1 = walls[3]["normal"][pick] / width
    s3 = walls[2]["normal"][pick] / height
    eps = 1.0 - height / height[0]
    eps_v = 1.0 - width * height / (width[0] * height[0])
    ratio = (s1 - s3) / np.maximum(s1 + s3, 1e-300)
    return eps, eps_v, ratio, s1, s3


def binned(eps, values, step):
    """Means of values in strain bins of width step (empty bins left out)."""
    edges = np.arange(0.0, eps.max() + step, step)
    centre, mean = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        pick = (eps >= a) & (eps < b)
        if pick.any():
            centre.append(0.5 * (a + b))
            mean.append(values[pick].mean())
    return np.array(centre), np.array(mean)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--stage", default="compress")
    ap.add_argument("--bin", type=float, default=0.01)
    ap.add_argument("--critical", default="0.12,0.25")
    a = ap.parse_args()
    c0, c1 = (float(v) for v in a.critical.split(","))
    eps, eps_v, ratio, s1, s3 = curve(read_walls(a.out), a.stage)
    centre, mean = binned(eps, ratio, a.bin)
    _, vol = binned(eps, eps_v, a.bin)
    _, side = binned(eps, s3, a.bin)
    write_curve(os.path.join(a.out, "stress_strain.csv"), "biaxial stress-strain curve",
                ["eps_axial [1]", "sin_phi [1]", "eps_vol [1]", "sigma_3 [N/m]"],
                [centre, mean, vol, side])
    before = np.flatnonzero(centre < c0)  # the peak comes before the critical state
    if before.size == 0:
        raise SystemExit("no strain bin below the critical window")
    k = int(before[np.argmax(mean[before])])
    crit = mean[(centre >= c0) & (centre <= c1)]
    if crit.size < 2:
        raise SystemExit("the run reaches axial strain %.3f, short of the critical window" %
                         eps.max())
    # the bins' means, not the rows, as samples: rows a few steps apart are correlated
    crit_mean, crit_err = crit.mean(), crit.std(ddof=1) / math.sqrt(crit.size)
    deg = math.degrees
    print("rows %d, axial strain 0 .. %.3f, sigma_3 %.0f .. %.0f N/m" %
          (eps.size, eps.max(), s3[eps > 0.005].min(), s3.max()))
    print("peak: sin phi %.3f at strain %.3f (phi %.1f deg, tan phi %.3f)" %
          (mean[k], centre[k], deg(math.asin(mean[k])), math.tan(math.asin(mean[k]))))
    print("critical state (strain %.2f-%.2f): sin phi %.3f +- %.3f (phi %.1f deg, tan phi %.3f)" %
          (c0, c1, crit_mean, crit_err, deg(math.asin(crit_mean)),
           math.tan(math.asin(crit_mean))))
    print("volumetric strain at the end %.4f (negative: dilation)" % eps_v[-1])


if __name__ == "__main__":
    main()
