# SPDX-License-Identifier: MIT
"""Shared set-up of the Python tests: the source tree's python/ on sys.path (unless sablier is
installed and SABLIER_TEST_INSTALLED is set), the source dir, the `sablier` command."""
import os
import sys

SOURCE_DIR = os.environ.get("SABLIER_SOURCE_DIR") or os.path.dirname(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if not os.environ.get("SABLIER_TEST_INSTALLED"):
    sys.path.insert(0, os.path.join(SOURCE_DIR, "python"))

import sablier  # noqa: E402
from sablier import _loader  # noqa: E402


def scene_path(*parts):
    return os.path.join(SOURCE_DIR, "scenes", *parts)


def executable():
    return _loader.executable()


def has_scene_library():
    try:
        return sablier._capi.scene() is not None
    except OSError:
        return False


# The golden trajectories of tests/sim/test_golden.c, recorded from the C library: 150 grains
# rained into a box with a base row of fixed grains, 3000 steps.
GOLDEN = {
    "frictionless": ("none", "off", "linear", 0, 0, 0x6b5ac70819feb7fe),
    "frictionless_clip": ("none", "off", "linear", 1, 0, 0x0a9ad7aa57555e69),
    "regularised_clip": ("regularised", "off", "linear", 1, 0, 0x6beecc5fb9ec1bba),
    "spring": ("spring", "off", "linear", 0, 0, 0xc8461149ff8929db),
    "spring_two_species": ("spring", "off", "linear", 1, 1, 0xe933c0b51cf20a94),
    "spring_rolling_fixed": ("spring", "fixed", "linear", 1, 0, 0x38d5524e37e8c3a9),
    "spring_rolling_chord": ("spring", "chord", "linear", 1, 0, 0x061fb723223b1639),
    "rolling_only": ("none", "fixed", "linear", 1, 0, 0x72e9dc13d62957ac),
    "hertz_regularised": ("regularised", "off", "hertz", 1, 0, 0xbeff9c87bd5c735d),
    "periodic_spring": ("spring", "off", "linear", 1, 0, 0x731c20f928dec578),
}

G0 = 9.806


def golden_world(name):
    """The world of tests/sim/test_golden.c's make(), built from Python."""
    import numpy as np
    tangential, rolling, normal, clip, two_species, _ = GOLDEN[name]
    buf = sablier.GrainBuffer()
    buf.rain(7, x0=0.1, x1=1.9, y0=0.2, y1=1.8, radius_mean=0.05, polydispersity=0.08,
             pitch_radius=0.054, column_gap=0.005 * 0.054, row_gap=0.75 * 0.054,
             column_jitter=0.05, row_jitter=0.08, max_count=150)
    rained = buf.grains()
    n = rained.count
    buf.fixed_row(0.025, 1.975, 0.025, 0.025, 0, -1)
    g = buf.grains()
    k = np.arange(n)
    g.omega[:n] = (k % 5 - 2) * 3.0
    if two_species:
        g.species[:n][k % 3 == 0] = 1
    effects = []
    if tangential != "none":
        effects.append("friction")
    if rolling != "off":
        effects.append("rolling_resistance")
    periodic = name.startswith("periodic")
    if periodic:
        effects.append("periodic_x")
    materials = []
    for s in range(2 if two_species else 1):
        m = dict(density=1500.0 if s else 1000.0, k_n=3e5 if s else 1e5,
                 mu=0.3 if s else 0.5, gamma_s=20.0, restitution=0.3 if s else 0.6,
                 mu_r=0.002, k_r=5.0)
        m["k_t"] = 0.75 * m["k_n"]
        if normal == "hertz":
            del m["restitution"]
            m.update(k_n=3e6, gamma_n=2e3)
        materials.append(m)
    mobile = (g.flags & sablier.SIM_GRAIN_FIXED) == 0
    skin = 0.2 * np.sum(2.0 * g.radius[mobile]) / np.count_nonzero(mobile)
    walls = [(-1.0, 0.0, 3.0, 0.0, 0, -1)] if periodic else [
        (0.0, 0.0, 2.0, 0.0, 0, -1), (0.0, 0.0, 0.0, 3.0, 0, -1), (2.0, 0.0, 2.0, 3.0, 0, -1)]
    return sablier.World.from_arrays(
        grains=g, materials=materials, walls=walls, effects=effects, time_step=0.0,
        steps_per_contact=50.0, gravity=(0.0, -G0), max_dt_fraction=0.0, guard_max_speed=1e3,
        contact=dict(normal=normal, tangential=tangential, rolling=rolling, clip_tensile=clip),
        skin=skin, domain=(0.0, 2.0) if periodic else None)
