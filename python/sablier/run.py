# SPDX-License-Identifier: MIT
"""Whole scene runs: in this process with callbacks between steps (Run, through
libsablier-scene's stage runner), or through the `sablier` command (run(), which also makes
the scene's figures and movies)."""
import errno
import os
import subprocess
import tempfile

from . import _capi as C
from . import _loader
from .outputs import RunOutputs
from .scene import Scene, _sets_list


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
    if not os.path.isfile(scene):
        raise FileNotFoundError(errno.ENOENT, "sablier: no scene file", os.fspath(scene))
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


class Run:
    """The stage runner of `sablier run` in this process (app/run/run.h scene_run): every stage of
    a scene, its outputs written to `out` (a new temporary folder when None) as the command
    writes them, without figures or movies. A callback sees the stage's world between steps:

        def servo(world, stage, step):      # world: a sablier.World valid during the call
            f = world.frame()
            ...
            world.set_velocities(vx, vy, ids=f.id[:f.mobile_count])
        out = sablier.Run("scenes/x.scene", "out/x").stages(callback=servo, every=100)

    threads: of the physics step (the same bits for any count; 0: automatic)."""

    def __init__(self, scene, out=None, sets=None, threads=1, quiet=True):
        self.scene = scene if isinstance(scene, Scene) else Scene(scene, sets)
        self.out = os.fspath(out) if out is not None else tempfile.mkdtemp(prefix="sablier-")
        self.threads = int(threads)
        self.quiet = bool(quiet)

    def stages(self, callback=None, every=100, pandas=None):
        """Run every stage; callback(world, stage_name, step) at each stage's step 0, every
        `every` steps and at its last step, after that step's outputs: it may read the world
        (frame, coarse, energy) and change it (set_grains, set_velocities, gravity,
        set_motion). An exception in the callback stops the run and is raised again here.
        Returns RunOutputs(out); RunError for a failed run (returncode as the command's)."""
        from .world import World
        every = int(every)
        if every < 1:
            raise ValueError("every = %d: callbacks need a period of at least one step" % every)
        lib = C.scene()
        scene = self.scene
        raised = []

        def hook(_context, handle, stage, step):
            world = World._borrow(handle, scene.world_def(stage))
            try:
                callback(world, scene.stage_names[stage], step)
            except BaseException as e:  # noqa: B902 - raised again after the run
                raised.append(e)
                return 1
            finally:
                world.close()
            return 0

        c_hook = C.RUN_HOOK(hook) if callback is not None else C.RUN_HOOK()
        status = lib.scene_run(scene._p, self.out.encode(), int(self.quiet), self.threads,
                               c_hook, None, every)
        outputs = RunOutputs(self.out, pandas)
        if raised:
            raise raised[0]
        if status != 0:
            raise RunError("sablier: the run of %s into %s failed: exit status %d"
                           % (scene.path, self.out, status), status, None, outputs)
        return outputs

    stage = stages  # sablier.Run(scene).stage(callback=f, every=100)
