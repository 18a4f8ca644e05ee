# SPDX-License-Identifier: MIT
"""Runs `sablier run` members for the analyses of docs/experiments.md (janssen.py, mu_of_i.py,
impact.py): each member a scene with its --set overrides into its own folder, `jobs` at a time;
a folder that already holds a finished run (its summary.json) is kept, so an interrupted study
goes on. Reads a member's final grains back (`sablier export`) and their free surface."""
import os
import subprocess
import time

import numpy as np


def run_members(sablier, scene, members, jobs=2):
    """members: a list of (out_dir, [KEY=VALUE, ...]). Raises SystemExit on a failed member."""
    todo = [m for m in members if not os.path.exists(os.path.join(m[0], "summary.json"))]
    running = []
    while todo or running:
        while todo and len(running) < jobs:
            out, sets = todo.pop(0)
            cmd = [sablier, "run", scene, "--out", out, "--quiet", "--threads", "1"]
            for s in sets:
                cmd += ["--set", s]
            log = open(out + ".log", "w")
            running.append((out, log, subprocess.Popen(cmd, stdout=log, stderr=log)))
        for item in list(running):
            out, log, proc = item
            if proc.poll() is None:
                continue
            log.close()
            running.remove(item)
            if proc.returncode != 0:
                raise SystemExit("%s failed (exit %d): see %s.log" % (out, proc.returncode, out))
        time.sleep(0.1)


def export_csv(sablier, state, csv_path):
    """The grains of a checkpoint as CSV (`sablier export --format csv`), read back with numpy."""
    subprocess.run([sablier, "export", state, "-o", csv_path, "--format", "csv"], check=True,
                   stdout=subprocess.DEVNULL)
    return np.genfromtxt(csv_path, delimiter=",", names=True)


def top_surface(grains, x0, x1, columns):
    """Mean over `columns` equal columns of [x0, x1] of the highest grain top y + r (m)."""
    edges = np.linspace(x0, x1, columns + 1)
    tops = []
    for a, b in zip(edges[:-1], edges[1:]):
        pick = (grains["x"] >= a) & (grains["x"] < b)
        if pick.any():
            tops.append((grains["y"][pick] + grains["r"][pick]).max())
    return float(np.mean(tops))
