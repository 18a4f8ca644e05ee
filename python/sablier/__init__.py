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
    sablier.Run("scenes/x.scene", "out/x").stages(callback=f, every=100)  # in this process
"""
from . import _capi, _loader
from .outputs import RunOutputs, load, read_csv, read_key_values
from .render import available as render_available
from .run import Run, RunError, command, run
from .scene import Scene
from .definition import (GrainBuffer, Grains, InvalidDefinition, OutOfMemory, SablierError,
                         StateIOError, Unstable, WorldDef, effects_bits, effects_names, material)
from .world import Frame, StaleFrame, World

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


_ISA_COUNT = 4  # SIM_ISA_COUNT (sim/sim.h)


def isa():
    """Name of the instruction set of the hot loops that new worlds use: "sse2", "avx2",
    "avx512" or "native" (sim_isa; docs/dev/isa.md). Every set gives the same bits."""
    lib = _capi.sim()
    return lib.sim_isa_name(lib.sim_isa()).decode()


def isa_supported():
    """The sets this library and CPU run, slowest first."""
    lib = _capi.sim()
    return [lib.sim_isa_name(k).decode() for k in range(_ISA_COUNT) if lib.sim_isa_supported(k)]


def set_isa(name):
    """Choose the set for worlds created afterwards (sim_isa_set); ValueError if unsupported."""
    lib = _capi.sim()
    k = lib.sim_isa_from_name(name.encode())
    if k < 0 or lib.sim_isa_set(k) != 0:
        raise ValueError("sablier: instruction set %r is not supported here (%s)"
                         % (name, ", ".join(isa_supported())))


__all__ = ["World", "WorldDef", "Frame", "StaleFrame", "Run", "Grains", "GrainBuffer", "Scene", "material", "run",
           "command", "load", "read_csv", "read_key_values", "RunOutputs", "RunError",
           "SablierError", "InvalidDefinition", "Unstable", "StateIOError", "OutOfMemory",
           "effects_bits", "effects_names", "library_path", "render_available",
           "SIM_GRAIN_FIXED", "isa", "isa_supported", "set_isa"]
