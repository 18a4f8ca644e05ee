#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Janssen's law from scenes/silo/janssen.scene: the base load against the fill height.

    /usr/bin/python3 scripts/experiments/janssen.py [--sablier build/sablier]
        [--counts 100,200,300,400,500,600] [--seeds 2] [--jobs 2] [--out out/janssen-study]

Runs the scene once per grain count (`sources.feed.count`) and seed, into OUT/nN-sS/, reads
each member's steady wall loads (summary.json's walls.mean over output.walls.window): the base
load F_b = -fy of wall 0 and the weight W = -(sum of every wall's fy). The fill height is
h = W / (rho_b g D), rho_b g D the median over the members of W over the surface height (the
mean over five columns of the final state's highest grain top). Janssen (1895) in a slot of
width D between two walls with friction mobilised up to mu_w and a stress ratio K =
sigma_xx / sigma_yy: d sigma_yy / dz = rho_b g - 2 K mu_w sigma_yy / D, so

    F_b = D sigma_yy(h) = (W / h) lambda (1 - exp(-h / lambda)),   lambda = D / (2 K mu_w),

one parameter lambda. lambda is fitted by least
squares on F_b / W (a scan in log lambda, refined); K mu_w = D / (2 lambda). Writes
OUT/janssen.csv (plot data: h, W, F_b, the fit) and prints the numbers."""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from members import export_csv, run_members, top_surface  # noqa: E402
from walls_table import read_summary, write_curve  # noqa: E402

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCENE = os.path.join(REPO, "scenes", "silo", "janssen.scene")
WIDTH = 1.0  # D: the scene's base from x = 0 to 1
FEED_RATE = 100.0  # grains/s: the scene's sources.feed.rate
SETTLE = 5.0  # s after the last grain: its fall (about 3.5 s at the drag's terminal speed) and rest


def janssen_fraction(h, lam):
    """F_b / W of Janssen's law at fill height h."""
    return lam / h * (1.0 - np.exp(-h / lam))


def fit_lambda(h, frac):
    """Least-squares lambda of janssen_fraction against the measured F_b / W."""
    def cost(lam):
        return float(np.sum((janssen_fraction(h, lam) - frac) ** 2))
    grid = np.exp(np.linspace(math.log(0.05 * h.min()), math.log(1e3 * h.max()), 400))
    k = int(np.argmin([cost(v) for v in grid]))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    for _ in range(60):  # golden-section refinement within the bracketing grid cells
        a = hi - 0.618 * (hi - lo)
        b = lo + 0.618 * (hi - lo)
        if cost(a) < cost(b):
            hi = b
        else:
            lo = a
    return 0.5 * (lo + hi)


def member_sets(count, seed):
    """The overrides of one member: `count` grains fed at the scene's 100 grains/s, then
    SETTLE s of rest, the wall loads averaged over its last half second."""
    end = count / FEED_RATE + SETTLE
    return ["sources.feed.count=%d" % count, "seed=%d" % seed, "time.end=%g" % end,
            "stages.fill.time.end=%g" % end, "output.walls.window=[%g,%g]" % (end - 0.5, end)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sablier", default=os.path.join(REPO, "build", "sablier"))
    ap.add_argument("--counts", default="100,200,300,400,500,600")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="out/janssen-study")
    ap.add_argument("--set", action="append", default=[], help="KEY=VALUE for every member")
    a = ap.parse_args()
    counts = [int(v) for v in a.counts.split(",")]
    os.makedirs(a.out, exist_ok=True)
    members = [(os.path.join(a.out, "n%d-s%d" % (n, s)), member_sets(n, s) + a.set)
               for n in counts for s in range(1, a.seeds + 1)]
    run_members(a.sablier, SCENE, members, a.jobs)
    surface, weight, base = [], [], []
    for out, _ in members:
        fy = [m["fy"] for m in read_summary(out)["walls"]["mean"]]
        grains = export_csv(a.sablier, os.path.join(out, "fill.state"),
                            os.path.join(out, "fill.csv"))
        surface.append(top_surface(grains, 0.0, WIDTH, 5))
        weight.append(-sum(fy))
        base.append(-fy[0])
    surface, weight, base = np.array(surface), np.array(weight), np.array(base)
    # the fill height from the weight: one grain standing proud of a low fill's surface shifts
    # its highest tops, not its weight
    line_weight = float(np.median(weight / surface))  # rho_b g D, N/m
    h = weight / line_weight
    lam = fit_lambda(h, base / weight)
    fit = weight * janssen_fraction(h, lam)
    order = np.argsort(h)
    write_curve(os.path.join(a.out, "janssen.csv"), "Janssen base load against fill height",
                ["h [m]", "W [N]", "F_base [N]", "F_base_fit [N]"],
                [h[order], weight[order], base[order], fit[order]])
    rms = math.sqrt(float(np.mean((base / weight - fit / weight) ** 2)))
    for k in order:
        print("h %6.3f m (%4.2f D)  W %8.0f N  F_base %8.0f N  F_base/W %.3f  fit %.3f" %
              (h[k], h[k] / WIDTH, weight[k], base[k], base[k] / weight[k], fit[k] / weight[k]))
    print("Janssen fit: lambda %.2f m (%.2f D), K mu_w %.4f, rms of F_base/W %.3f" %
          (lam, lam / WIDTH, WIDTH / (2.0 * lam), rms))
    print("saturation load rho_b g D lambda %.0f N (rho_b g D = median W / surface height %.0f N/m)"
          % (line_weight * lam, line_weight))


if __name__ == "__main__":
    main()
