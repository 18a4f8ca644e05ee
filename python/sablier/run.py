# SPDX-License-Identifier: MIT
"""Whole scene runs through the `sablier` command (the stage runner, experiment families,
figures and movies live in the command, not in the libraries)."""
import os
import subprocess

from . import _loader
from .outputs import RunOutputs
from .scene import _sets_list


class RunError(RuntimeError):
    """`sablier run` failed: returncode 1 = unstable (last good state saved), 2 = bad input."""

    def __init__(self, message, returncode, stderr, out):
        super().__init__(message)
        self.returncode = returncode
        self.stderr = stderr
        self.out = out


def command(*args, check=True, executable=None, capture=True):
    """Run `sablier ARGS...`; returns subprocess.CompletedProcess (text)."""
    exe = executable or _loader.executable()
    if exe is None:
        raise OSError("sablier: the `sablier` command was not found (set SABLIER_EXECUTABLE, "
                      "SABLIER_LIB_DIR to a build tree, or put it on PATH)")
    cmd = [exe] + [os.fspath(a) for a in args]
    r = subprocess.run(cmd, capture_output=capture, text=True)
    if check and r.returncode != 0:
        raise RunError("%s: exit status %d\n%s" % (" ".join(cmd), r.returncode, r.stderr or ""),
                       r.returncode, r.stderr, None)
    return r


def run(scene, out, sets=None, quiet=True, threads=None, check=True, executable=None,
        pandas=None):
    """`sablier run SCENE --out OUT [--set K=V]...`; returns RunOutputs(out). sets: a dict
    {"time.end": 30} or a list of "KEY=VALUE". check=True raises RunError on a non-zero exit
    (the outputs written so far stay in `out`: RunError.out). threads: a count or "auto";
    None leaves the CLI's default, auto (every CPU, one thread per 1000 mobile grains)."""
    args = ["run", scene, "--out", out]
    for s in _sets_list(sets):
        args += ["--set", s]
    if quiet:
        args.append("--quiet")
    if threads is not None:
        args += ["--threads", str(threads)]
    outputs = RunOutputs(out, pandas)
    try:
        command(*args, check=check, executable=executable)
    except RunError as e:
        e.out = outputs
        raise
    return outputs
