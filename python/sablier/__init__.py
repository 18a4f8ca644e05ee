# SPDX-License-Identifier: MIT
"""sablier: 2D soft-disk DEM from Python (ctypes over libsablier-sim, libsablier-render and
libsablier-scene; NumPy). docs/python.md.

    import sablier
    w = sablier.World.from_arrays(x, y, radius, walls=[(0, 0, 1, 0)], time_step=1e-5)
    w.step(1000)
    f = w.frame()          # NumPy views over the C arrays, valid until the next step
    print(f.y.max(), w.hash())
    out = sablier.run("scenes/brazil_nut/small.scene", "out/bne", sets={"time.end": 30})
    bne = out.bne          # bne.csv as a structured array (or a DataFrame with pandas)
"""
from . import _capi, _loader
from .outputs import RunOutputs, load, read_csv, read_key_values
from .render import available as render_available
from .run import RunError, command, run
from .scene import Scene
from .world import (Frame, GrainBuffer, Grains, InvalidDefinition, OutOfMemory, SablierError,
                    StateIOError, Unstable, World, WorldDef, effects_bits, effects_names,
                    material)

__version__ = "0.1.0"

SIM_GRAIN_FIXED = _capi.SIM_GRAIN_FIXED


def library_path(name="sablier-sim"):
    """Path of the shared library NAME that this module uses (loading it if needed)."""
    if name == "sablier-sim":
        _capi.sim()
    elif name == "sablier-render":
        _capi.render()
    elif name == "sablier-scene":
        _capi.scene()
    return _loader.path_of(name)


def sim_version():
    return "0.1.0"


__all__ = ["World", "WorldDef", "Frame", "Grains", "GrainBuffer", "Scene", "material", "run",
           "command", "load", "read_csv", "read_key_values", "RunOutputs", "RunError",
           "SablierError", "InvalidDefinition", "Unstable", "StateIOError", "OutOfMemory",
           "effects_bits", "effects_names", "library_path", "render_available",
           "SIM_GRAIN_FIXED"]
