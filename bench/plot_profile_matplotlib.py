#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""profile.csv (t,t_stage,stage,x,y: a crater run's free-surface profiles) drawn by matplotlib
with its defaults (6.4 x 4.8 in, 100 dpi, DejaVu Sans 10 pt, legend "best"): the reference of
docs/figures.md#sablier-and-matplotlib, timed by bench/plot_vs_matplotlib.sh.

  plot_profile_matplotlib.py PROFILE_CSV OUT_DIR [REPEATS]

Writes OUT_DIR/profiles_matplotlib.png and .pdf; prints the import time and the mean time per
figure (CSV read, PNG and PDF written)."""
import csv
import sys
import time

t0 = time.perf_counter()
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

t_import = time.perf_counter() - t0


def curves(path, count=8):
    """The last stage's profiles at `count` evenly spaced sample times."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    stage = rows[-1]["stage"]
    rows = [r for r in rows if r["stage"] == stage]
    times = sorted({float(r["t_stage"]) for r in rows})
    picks = sorted({times[round(k * (len(times) - 1) / max(count - 1, 1))] for k in range(count)})
    out = []
    for t in picks:
        xs = [float(r["x"]) for r in rows if float(r["t_stage"]) == t]
        ys = [float(r["y"]) for r in rows if float(r["t_stage"]) == t]
        out.append((t, xs, ys))
    return out


def draw(path, out_dir):
    fig, ax = plt.subplots()
    for t, xs, ys in curves(path):
        ax.plot(xs, ys, label="$t - t_0$ = %.2f s" % t)
    ax.set_xlabel("$x$ (m)")
    ax.set_ylabel("free surface $y$ (m)")
    ax.set_title("free-surface profiles")
    ax.legend()
    fig.savefig(out_dir + "/profiles_matplotlib.png")
    fig.savefig(out_dir + "/profiles_matplotlib.pdf")
    plt.close(fig)


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    repeats = int(argv[3]) if len(argv) > 3 else 20
    start = time.perf_counter()
    for _ in range(repeats):
        draw(argv[1], argv[2])
    per = (time.perf_counter() - start) / repeats
    print("matplotlib %s: import %.0f ms, %.1f ms per figure (profile.csv read, PNG and PDF "
          "written), %d repeats" % (matplotlib.__version__, 1e3 * t_import, 1e3 * per, repeats))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
