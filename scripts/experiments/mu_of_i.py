#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""mu(I) from scenes/shear/plane_shear.scene: a sweep over the base speed at constant pressure.

    /usr/bin/python3 scripts/experiments/mu_of_i.py [--sablier build/sablier]
        [--speeds 0.1,0.3,1,2,4,8] [--jobs 2] [--out out/plane-shear-study] [--set KEY=VALUE]

Runs the scene once per base speed V (`motions.slide.velocity = [V, 0]`) into OUT/vV/, then over
each member's output.walls.window (the second half of the shear stage):
  - mu = <F_x> / <N> of the lid (wall 0): its tangential load over its normal load, the
    friction coefficient tau / P (the lid is the period long, so both are per the same length);
  - the shear rate gamma_dot: the slope of a least-squares line through the x-velocity profile
    (profile.csv, coarse-grained, averaged over the window) over the bins at least 2 d from the
    base and from the lid; the flat lid lets the grains next to it slide, so V / H is not the
    shear rate;
  - the inertial number I = gamma_dot d / sqrt(P / rho) (GDR MiDi 2004; 2D: P in N/m, rho in
    kg/m^2, d the mean diameter), P the lid's mean stress.
Fits mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1) (Jop, Forterre and Pouliquen 2006), linear in
mu_s and mu_2 at fixed I_0, I_0 scanned in log. Writes OUT/mu_of_i.csv (plot data) and prints
the numbers."""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from members import run_members  # noqa: E402
from walls_table import read_summary, read_walls, write_curve  # noqa: E402

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE = os.path.join(REPO, "scenes", "shear", "plane_shear.scene")
DIAMETER = 0.1  # m: the scene's mean grain diameter (radius_mean 0.05)
DENSITY = 1000.0  # kg/m^2: the grains' density (disks)
LID_Y0 = 2.45  # m: the lid's height before it moves (its offset is along -y)


def bin_mean(values):
    """Mean of a profile bin's finite samples (a bin no grain reached is NaN), NaN if none."""
    finite = values[np.isfinite(values)]
    return float(finite.mean()) if finite.size else float("nan")


def member_numbers(out):
    """mu, I, P, gamma_dot and the lid's height of one member over its walls window."""
    summary = read_summary(out)
    t0, t1 = summary["walls"]["window"]
    lid = read_walls(out)[0]
    pick = (lid["t"] >= t0) & ((lid["t"] <= t1) | (t1 < 0))
    mu = lid["fx"][pick].mean() / lid["normal"][pick].mean()
    pressure = lid["stress"][pick].mean()
    top = LID_Y0 - lid["offset"][pick].mean()
    prof = np.genfromtxt(os.path.join(out, "profile.csv"), delimiter=",", names=True)
    rows = prof["t"] >= t0
    ys = np.unique(prof["y"][rows])
    vx = np.array([bin_mean(prof["vx"][rows & (prof["y"] == y)]) for y in ys])
    bulk = (ys >= 2.0 * DIAMETER) & (ys <= top - 2.0 * DIAMETER) & np.isfinite(vx)
    if bulk.sum() < 3:
        raise SystemExit("%s: fewer than 3 profile bins in the bulk" % out)
    gamma_dot = -np.polyfit(ys[bulk], vx[bulk], 1)[0]  # the base drives +x, the lid holds
    inertial = gamma_dot * DIAMETER / math.sqrt(pressure / DENSITY)
    return mu, inertial, pressure, gamma_dot, top


def fit_mu_of_i(inertial, mu):
    """Least-squares (mu_s, mu_2, I_0) of Jop et al.'s mu(I)."""
    best = None
    for i0 in np.exp(np.linspace(math.log(1e-4), math.log(10.0), 801)):
        shape = inertial / (i0 + inertial)
        design = np.column_stack([np.ones_like(shape), shape])
        coef, *_ = np.linalg.lstsq(design, mu, rcond=None)
        cost = float(np.sum((design @ coef - mu) ** 2))
        if best is None or cost < best[0]:
            best = (cost, coef[0], coef[0] + coef[1], i0)
    return best[1], best[2], best[3], math.sqrt(best[0] / mu.size)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sablier", default=os.path.join(REPO, "build", "sablier"))
    ap.add_argument("--speeds", default="0.1,0.3,1,2,4,8")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="out/plane-shear-study")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE for every member")
    a = ap.parse_args()
    speeds = [float(v) for v in a.speeds.split(",")]
    os.makedirs(a.out, exist_ok=True)
    members = [(os.path.join(a.out, "v%g" % v), ["motions.slide.velocity=[%.17g,0.0]" % v] + a.set)
               for v in speeds]
    run_members(a.sablier, SCENE, members, a.jobs)
    numbers = np.array([member_numbers(out) for out, _ in members])
    mu, inertial = numbers[:, 0], numbers[:, 1]
    mu_s, mu_2, i0, rms = fit_mu_of_i(inertial, mu)
    fit = mu_s + (mu_2 - mu_s) / (i0 / inertial + 1.0)
    write_curve(os.path.join(a.out, "mu_of_i.csv"), "mu against the inertial number",
                ["V [m/s]", "I [1]", "mu [1]", "mu_fit [1]", "P [N/m]", "gamma_dot [1/s]"],
                [speeds, inertial, mu, fit, numbers[:, 2], numbers[:, 3]])
    for v, row, f in zip(speeds, numbers, fit):
        print("V %5.2f m/s  gamma_dot %7.4f 1/s  P %6.0f N/m  I %.4f  mu %.3f  fit %.3f  "
              "layer %.2f m" % (v, row[3], row[2], row[1], row[0], f, row[4]))
    print("mu(I) fit: mu_s %.3f, mu_2 %.3f, I_0 %.3f (rms %.3f)" % (mu_s, mu_2, i0, rms))


if __name__ == "__main__":
    main()
