# SPDX-License-Identifier: MIT
"""A run's outputs (energy.csv, bne.csv, profile.csv, crater.csv, trace.csv, observables.csv,
summary.json, bne.json, ...) as NumPy structured arrays, pandas DataFrames or dicts."""
import csv
import io
import json
import os

import numpy as np


def have_pandas():
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def _column(values):
    """float64 when every value is a number (counts included: one rule, whatever a column
    happens to hold; empty cells are NaN), else str."""
    try:
        return np.array([float(v) if v != "" else np.nan for v in values], dtype=np.float64)
    except ValueError:
        width = max((len(v) for v in values), default=1)
        return np.array(values, dtype="U%d" % max(width, 1))


def read_csv(path, pandas=None):
    """A CSV file with a header line as a NumPy structured array (one field per column: float64
    when every value is a number, else str; empty cells of numeric columns are NaN), or a
    pandas DataFrame: pandas=True, or pandas=None (the default) when pandas is importable.
    pandas=False always gives NumPy. Lines starting with '#' are skipped."""
    with open(path, newline="") as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    if pandas or (pandas is None and have_pandas()):
        import pandas as pd
        return pd.read_csv(io.StringIO("".join(lines)))
    rows = list(csv.reader(lines))
    if not rows:
        return np.zeros(0, dtype=[])
    header, body = rows[0], [r for r in rows[1:] if r]
    cols = [_column([r[k] if k < len(r) else "" for r in body]) for k in range(len(header))]
    out = np.empty(len(body), dtype=[(h, c.dtype) for h, c in zip(header, cols)])
    for h, c in zip(header, cols):
        out[h] = c
    return out


def read_key_values(path):
    """A key,value CSV (observables.csv) as a dict of floats (strings where not numbers)."""
    out = {}
    with open(path, newline="") as f:
        rows = list(csv.reader(ln for ln in f if not ln.startswith("#")))
    for r in rows[1:] if rows and rows[0][:2] == ["key", "value"] else rows:
        if len(r) >= 2:
            try:
                out[r[0]] = float(r[1])
            except ValueError:
                out[r[0]] = r[1]
    return out


class RunOutputs:
    """The outputs of one run folder. Attributes are read on first use (None when the file is
    absent): energy, bne, profile, crater, trace, phase_field, samples, rise (CSV tables),
    observables (dict), summary, bne_json (dicts from JSON); states: {stage: path};
    figures: [paths]; table(name) reads any other <name>.csv. `pandas` as in read_csv."""

    TABLES = ("energy", "bne", "profile", "crater", "trace", "phase_field", "phase_fields",
              "samples", "rise", "ldf", "sweep")

    def __init__(self, directory, pandas=None):
        self.dir = os.fspath(directory)
        self.pandas = pandas
        self._cache = {}

    def path(self, name):
        return os.path.join(self.dir, name)

    def table(self, name):
        if name not in self._cache:
            p = self.path(name + ".csv")
            self._cache[name] = read_csv(p, self.pandas) if os.path.isfile(p) else None
        return self._cache[name]

    def __getattr__(self, name):
        if name in RunOutputs.TABLES:
            return self.table(name)
        raise AttributeError(name)

    def _json(self, name):
        p = self.path(name)
        if not os.path.isfile(p):
            return None
        with open(p) as f:
            return json.load(f)

    @property
    def summary(self):
        return self._json("summary.json")

    @property
    def bne_json(self):
        return self._json("bne.json")

    @property
    def observables(self):
        p = self.path("observables.csv")
        return read_key_values(p) if os.path.isfile(p) else None

    @property
    def states(self):
        out = {}
        for n in sorted(os.listdir(self.dir)):
            if n.endswith(".state") and not n.endswith(".last_good.state"):
                out[n[:-len(".state")]] = self.path(n)
        return out

    @property
    def figures(self):
        return [self.path(n) for n in sorted(os.listdir(self.dir))
                if n.endswith((".png", ".pdf", ".svg"))]

    def __repr__(self):
        return "RunOutputs(%r)" % self.dir


def load(directory, pandas=None):
    """RunOutputs of a run folder (sablier run --out DIR)."""
    return RunOutputs(directory, pandas)
