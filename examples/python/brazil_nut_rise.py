#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Brazil-nut rise curve from Python (docs/python.md): runs the reduced Brazil-nut box
(scenes/brazil_nut/small.scene, 300 grains and a 5 d intruder shaken at Gamma = 3) for a few
seeds through the `sablier` command, loads each run's bne.csv and computes the mean rise of the
intruder h(t) - h(0) against the number of shaking periods, cycle-averaged (at Gamma = 3 the
bed flies: one sample is at an arbitrary phase of the cycle).

    /usr/bin/python3 examples/python/brazil_nut_rise.py [OUT] [--seeds N] [--shake T]

Writes OUT/rise.csv and OUT/rise.png (matplotlib when importable, else the final state of the
first seed drawn by sablier's renderer as OUT/final.png). Default OUT: out/py-brazil-nut.
"""
import argparse
import os
import sys

import numpy as np

# run from a source checkout without installing: python/ next to examples/
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "python"))
import sablier  # noqa: E402

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("out", nargs="?", default="out/py-brazil-nut")
p.add_argument("--seeds", type=int, default=4)
p.add_argument("--shake", type=float, default=60.0, help="shaking time, d/g units")
args = p.parse_args()
scene = os.path.join(ROOT, "scenes", "brazil_nut", "small.scene")

# 1. the runs: the scene's own two stages (settle, then shake), the shaking shortened
runs = []
for seed in range(1, args.seeds + 1):
    out = sablier.run(scene, os.path.join(args.out, "seed-%d" % seed), pandas=False,
                      sets={"seed": seed, "stages.shake.time.end": args.shake})
    runs.append(out)
    print("seed %d: rise rate %.3f d per time unit" % (seed, out.bne_json["rise_rate"]))

# 2. the rise h(t) - h(0) of the intruder's centre in the box frame, per seed
period = runs[0].bne_json["period"]
t = np.arange(0.0, args.shake + 1e-9, 0.5)            # bne.csv rows: every output.energy_every
rise = np.array([np.interp(t, r.bne["t_shake"], r.bne["intruder_y"] - r.bne["intruder_y"][0])
                 for r in runs])

# 3. cycle averages: the mean over each whole period, then over seeds
cycles = int(args.shake // period)
k = np.arange(cycles)
per_cycle = np.array([[seed_rise[(t >= c * period) & (t < (c + 1) * period)].mean()
                       for c in k] for seed_rise in rise])
mean, spread = per_cycle.mean(axis=0), per_cycle.std(axis=0, ddof=1) if len(runs) > 1 else 0 * k

table = np.rec.fromarrays([k + 0.5, mean, spread], names="cycle,rise_mean,rise_std")
os.makedirs(args.out, exist_ok=True)
np.savetxt(os.path.join(args.out, "rise.csv"), table, delimiter=",", fmt="%.6g",
           header="cycle,rise_mean,rise_std", comments="")
for row in table[::max(1, cycles // 8)]:
    print("period %5.1f: rise %6.2f +- %.2f d" % tuple(row))

# 4. a figure: matplotlib if present, else sablier's renderer on the last state of seed 1
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
if plt is not None:
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for seed_rise in rise:
        ax.plot(t / period, seed_rise, lw=0.5, color="0.7")
    ax.errorbar(k + 0.5, mean, yerr=spread, marker="o", ms=3, capsize=2, label="cycle mean")
    ax.set_xlabel("shaking periods")
    ax.set_ylabel("rise h - h0 (d)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "rise.png"), dpi=150)
    print("wrote", os.path.join(args.out, "rise.png"))
else:
    world = sablier.World.from_state(runs[0].states["shake"], scene=scene)
    path = os.path.join(args.out, "final.png")
    try:
        world.render(path, color_by="species", width=400, height=800, view=(-1, -2, 16, 40),
                     title="seed 1 after %.0f periods" % (args.shake / period))
        print("wrote", path, "(no matplotlib: the final state)")
    except (OSError, RuntimeError, ValueError) as e:  # a build without rendering
        print("no figure: no matplotlib, and", e)
