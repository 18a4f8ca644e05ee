# SPDX-License-Identifier: MIT
"""Reads a run's walls.csv (docs/measures.md#forces-on-walls-outputwalls) for the analyses of
docs/experiments.md (biaxial.py, janssen.py, mu_of_i.py), and writes their curves as plot-data
CSV files (units in the header, docs/figures.md#plot-data). numpy only."""
import csv
import json
import os

import numpy as np

FLOATS = ("t", "fx", "fy", "normal", "tangential", "torque", "stress", "x", "y", "offset",
          "speed", "contacts")


def read_walls(run_dir):
    """walls.csv of run_dir as {wall index: {column: array}}; `stage` stays a list of strings."""
    with open(os.path.join(run_dir, "walls.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit("%s: walls.csv has no rows" % run_dir)
    walls = {}
    for k in sorted({int(r["wall"]) for r in rows}):
        mine = [r for r in rows if int(r["wall"]) == k]
        table = {c: np.array([float(r[c]) for r in mine]) for c in FLOATS}
        table["stage"] = [r["stage"] for r in mine]
        walls[k] = table
    return walls


def read_summary(run_dir):
    """summary.json of run_dir."""
    with open(os.path.join(run_dir, "summary.json")) as f:
        return json.load(f)


def write_curve(path, title, columns, data):
    """A plot-data CSV: a comment line naming the figure, a header of `name [unit]` columns,
    one row per point (17 significant digits), written to path.tmp and renamed."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# sablier plot data: %s (docs/experiments.md)\n" % title)
        f.write(",".join(columns) + "\n")
        for row in zip(*data):
            f.write(",".join("%.17g" % v for v in row) + "\n")
    os.replace(tmp, path)


def window_mean(values, t, t0, t1):
    """Mean and standard error of values over t0 <= t <= t1 (samples taken as independent)."""
    pick = (t >= t0) & (t <= t1)
    v = values[pick]
    if v.size < 2:
        raise SystemExit("window [%g, %g] holds %d samples" % (t0, t1, v.size))
    return float(v.mean()), float(v.std(ddof=1) / np.sqrt(v.size))
