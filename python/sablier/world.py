# SPDX-License-Identifier: MIT
"""Worlds: stepping, frame views as NumPy arrays, checkpoints, hashes (definitions: definition.py)."""
import ctypes
import os

import numpy as np

from . import _capi as C
from .definition import GrainBuffer, Grains, OutOfMemory, WorldDef, _ptr, _raise, effects_names
from .scene import Scene


class Frame:
    """A view of the world's state: NumPy arrays over the C library's own memory (no copies),
    in frame order (mobile grains first, then fixed grains; the order changes at neighbour-list
    builds: follow grains by `id`). Valid until the next call that changes the world (step,
    frame, energy and other diagnostics, edits, close): afterwards its arrays read freed or reused
    memory. Take `copy()` to keep values.

    Arrays: x, y, angle, radius, vx, vy, omega, species, flags, id, force (sum of contact-force
    magnitudes), fx, fy, torque; `contacts` is a structured array with fields i, j (j = -1 -
    wall index for a wall contact), normal_force, tangential_force, overlap, x, y, nx, ny (the
    unit normal from grain i towards j or the wall); `walls` has
    x0, y0, x1, y1, species, motion. Scalars: count, mobile_count, step, time, time_scale,
    periodic, domain_x0, domain_x1."""

    _ARRAYS = (("x", np.float64), ("y", np.float64), ("angle", np.float64),
               ("radius", np.float64), ("vx", np.float64), ("vy", np.float64),
               ("omega", np.float64), ("species", np.intc), ("flags", np.uintc),
               ("id", np.uint32), ("force", np.float64), ("fx", np.float64), ("fy", np.float64),
               ("torque", np.float64))
    CONTACT_DTYPE = np.dtype({"names": ["i", "j", "normal_force", "tangential_force", "overlap",
                                        "x", "y", "nx", "ny"],
                              "formats": [np.intc, np.intc] + [np.float64] * 7,
                              "offsets": [getattr(C.SimContact, f[0]).offset
                                          for f in C.SimContact._fields_],
                              "itemsize": ctypes.sizeof(C.SimContact)})
    WALL_DTYPE = np.dtype({"names": ["x0", "y0", "x1", "y1", "species", "motion"],
                           "formats": [np.float64] * 4 + [np.intc] * 2,
                           "offsets": [getattr(C.SimWall, f[0]).offset
                                       for f in C.SimWall._fields_],
                           "itemsize": ctypes.sizeof(C.SimWall)})

    def __init__(self, raw, owner=None):
        self.raw = raw
        self._owner = owner
        n = raw.count
        for name in ("count", "mobile_count", "step", "time", "time_scale", "periodic",
                     "domain_x0", "domain_x1"):
            setattr(self, name, getattr(raw, name))
        for name, dtype in self._ARRAYS:
            p = getattr(raw, name)
            if n and p:
                a = np.ctypeslib.as_array(p, shape=(n,))
                a.flags.writeable = False
            else:
                a = np.zeros(n if not p else 0, dtype)
            setattr(self, name, a)
        self.contacts = self._records(raw.contacts, raw.contact_count, C.SimContact,
                                      self.CONTACT_DTYPE)
        self.walls = self._records(raw.walls, raw.wall_count, C.SimWall, self.WALL_DTYPE)

    @staticmethod
    def _records(ptr, count, ctype, dtype):
        if count <= 0 or not ptr:
            return np.zeros(0, dtype)
        buf = (ctypes.c_char * (count * ctypes.sizeof(ctype))).from_address(
            ctypes.addressof(ptr.contents))
        a = np.frombuffer(buf, dtype=dtype, count=count)
        a.flags.writeable = False
        return a

    @property
    def positions(self):
        """(count, 2) array of x, y (a copy: x and y are separate C arrays)."""
        return np.column_stack((self.x, self.y))

    @property
    def velocities(self):
        return np.column_stack((self.vx, self.vy))

    @property
    def forces(self):
        return np.column_stack((self.fx, self.fy))

    @property
    def mobile(self):
        """Boolean mask of mobile grains (the first mobile_count)."""
        m = np.zeros(self.count, bool)
        m[:self.mobile_count] = True
        return m

    def index_of(self, ids):
        """Frame indices of stable ids (-1 when absent)."""
        ids = np.atleast_1d(np.asarray(ids, dtype=np.uint32))
        out = np.full(ids.shape, -1, dtype=np.intp)
        if self.count == 0:
            return out
        order = np.argsort(self.id, kind="stable")
        sorted_ids = self.id[order]
        pos = np.clip(np.searchsorted(sorted_ids, ids), 0, self.count - 1)
        hit = sorted_ids[pos] == ids
        out[hit] = order[pos[hit]]
        return out

    def copy(self):
        """A Frame whose arrays are NumPy copies (valid for ever)."""
        f = object.__new__(Frame)
        f.raw = None
        f._owner = None
        for name in ("count", "mobile_count", "step", "time", "time_scale", "periodic",
                     "domain_x0", "domain_x1"):
            setattr(f, name, getattr(self, name))
        for name, _ in self._ARRAYS:
            setattr(f, name, getattr(self, name).copy())
        f.contacts = self.contacts.copy()
        f.walls = self.walls.copy()
        return f


# ------------------------------------------------------------------ worlds


class World:
    """A simulation world (SimWorld). Build with World(definition), World.from_arrays,
    World.from_scene or World.from_state; close() (or a `with` block) frees it."""

    def __init__(self, definition, _handle=None):
        self._lib = C.sim()
        self.definition = definition
        if _handle is None:
            err = C.SimError()
            _handle = self._lib.sim_world_create(ctypes.byref(definition.raw), ctypes.byref(err))
            if not _handle:
                _raise(err, "sim_world_create")
        self._w = _handle
        self._dead = None
        self._frame = C.SimFrame()

    # -------------------------------------------------------- construction

    @classmethod
    def from_arrays(cls, x=None, y=None, radius=None, *, grains=None, species=None, fixed=None,
                    flags=None, vx=None, vy=None, angle=None, omega=None, motion=None, id=None,
                    walls=None, materials=None, effects=None, **options):
        """A world from arrays. Grains: x, y, radius (+ optional vx, vy, angle, omega, species,
        fixed or flags, motion, id), or grains= a Grains, a dict of those, or a GrainBuffer.
        walls: (x0, y0, x1, y1[, species[, motion]]) tuples. materials: list of dicts of
        SimMaterial fields (default: one sim_material_default()). effects: names. Other
        options are SimWorldDef fields by name (time_step, skin, gravity=(gx, gy),
        mass_model="disk"|"sphere", integrator="velocity_verlet"|..., contact=dict(normal,
        tangential, rolling, clip_tensile), domain=(x0, x1), motions, sinks, body_force,
        guard_*, max_initial_overlap, length_scale, start_time, ...)."""
        d = WorldDef()
        if grains is None:
            grains = Grains(x, y, radius, vx=vx, vy=vy, angle=angle, omega=omega,
                            species=species, flags=flags, motion=motion, id=id, fixed=fixed)
        d.set(grains=grains, effects=effects, **options)
        if materials is not None:
            d.set_materials(materials)
        if walls is not None:
            d.set_walls(walls)
        return cls(d)

    @classmethod
    def from_scene(cls, scene, sets=None, stage=0):
        """The world a scene's stage starts from when it builds from the scene's own grains
        (scene_world_def: materials, laws, walls, the stage's time step). A stage that
        continues from a previous one is built with World.from_state(checkpoint, scene=...).
        The stage runner's per-stage edits (digging, a bne shaking motion switched on, removals)
        are not applied: use sablier.run for whole runs. Needs libsablier-scene."""
        sc = scene if isinstance(scene, Scene) else Scene(scene, sets)
        return cls(sc.world_def(stage))

    @classmethod
    def from_state(cls, path, definition=None, scene=None, sets=None, stage=None,
                   restore_contacts=True, **options):
        """A world from a checkpoint (sim_world_save, a run's <stage>.state), with the materials
        and laws of `definition` (a WorldDef), of a scene's stage (scene= path or Scene;
        default stage: the one named like the state file, else the last), or of
        options as in from_arrays. restore_contacts: also reload the contact history (springs,
        rolling torques) and sink counts, so the run continues as it would have."""
        if definition is None:
            if scene is not None:
                sc = scene if isinstance(scene, Scene) else Scene(scene, sets)
                if stage is None:
                    base = os.path.basename(os.fspath(path))
                    name = base[:-len(".state")] if base.endswith(".state") else base
                    stage = name if name in sc.stage_names else sc.stage_count - 1
                definition = sc.world_def(stage)
            else:
                definition = WorldDef()
            definition.set(**options)
        lib = C.sim()
        err = C.SimError()
        bpath = C.as_bytes(path)
        handle = lib.sim_world_load(bpath, ctypes.byref(definition.raw), ctypes.byref(err))
        if not handle:
            _raise(err, "sim_world_load %s" % os.fspath(path))
        world = cls(definition, _handle=handle)
        if restore_contacts:
            if lib.sim_world_restore_contacts(handle, bpath, ctypes.byref(err)) != 0:
                world.close()
                _raise(err, "sim_world_restore_contacts %s" % os.fspath(path))
        return world

    # -------------------------------------------------------- life

    def close(self):
        if getattr(self, "_w", None):
            self._lib.sim_world_destroy(self._w)
            self._w = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _handle(self):
        if not self._w:
            raise ValueError("world is closed")
        if self._dead:
            raise OutOfMemory("world ran out of memory earlier (%s); only close() is left"
                              % self._dead, 4)
        return self._w

    # -------------------------------------------------------- stepping

    def step(self, steps=1):
        """Advance by `steps` time steps. Raises Unstable (rolled back to the last good state),
        OutOfMemory. Invalidates earlier Frame views."""
        w = self._handle()
        err = C.SimError()
        status = self._lib.sim_world_step(w, int(steps), ctypes.byref(err))
        body = getattr(self.definition, "_body", None)
        if body is not None and body.error is not None:
            e, body.error = body.error, None
            raise e
        if status == 4:
            self._dead = C.error_text(err)[0]
        if status != 0:
            _raise(err, "sim_world_step")
        return self

    def run_for(self, seconds):
        """Advance by round(seconds / dt) steps."""
        return self.step(int(round(seconds / self.time_step)))

    # -------------------------------------------------------- reading

    @property
    def time(self):
        return self._lib.sim_world_time(self._handle())

    @property
    def step_count(self):
        return self._lib.sim_world_step_count(self._handle())

    @property
    def time_step(self):
        return self._lib.sim_world_time_step(self._handle())

    @property
    def grain_count(self):
        return self._lib.sim_world_grain_count(self._handle())

    @property
    def mobile_count(self):
        return self._lib.sim_world_mobile_count(self._handle())

    @property
    def effects(self):
        return effects_names(self._lib.sim_world_effects(self._handle()))

    @property
    def threads(self):
        """Threads of the physics step (sim_world_set_threads; the same bits whatever the
        count); 1 with a library that has no threaded step."""
        if not hasattr(self._lib, "sim_world_threads"):
            return 1
        return self._lib.sim_world_threads(self._handle())

    @threads.setter
    def threads(self, count):
        if hasattr(self._lib, "sim_world_set_threads"):
            self._lib.sim_world_set_threads(self._handle(), int(count))

    @property
    def skin(self):
        return self._lib.sim_world_skin(self._handle())

    @property
    def list_builds(self):
        return self._lib.sim_world_list_builds(self._handle())

    def timing(self):
        t = self._lib.sim_world_timing(self._handle())
        return {f[0]: getattr(t, f[0]) for f in C.SimTiming._fields_}

    def frame(self):
        """A Frame: zero-copy NumPy views valid until the next call that changes the world."""
        self._lib.sim_world_frame(self._handle(), ctypes.byref(self._frame))
        return Frame(self._frame, self)

    def hash(self):
        """sim_world_hash: FNV-1a of positions, velocities and angles of all grains (the value
        the C tests and tools print; equal hashes = the same bits)."""
        return int(self._lib.sim_world_hash(self._handle()))

    def energy(self):
        """dict of SimEnergy: kinetic, potential, rotational, elastic, total (J), mobile,
        contacts."""
        e = self._lib.sim_world_energy(self._handle())
        return {f[0]: getattr(e, f[0]) for f in C.SimEnergy._fields_}

    def coordination(self):
        return self._lib.sim_world_coordination(self._handle())

    def packing_fraction(self, x0, y0, x1, y1):
        return self._lib.sim_world_packing_fraction(self._handle(), x0, y0, x1, y1)

    def max_overlap_ratio(self):
        return self._lib.sim_world_max_overlap_ratio(self._handle())

    def hexatic_order(self):
        return self._lib.sim_world_hexatic_order(self._handle())

    def means(self):
        """(mean diameter m, mean mass kg) of mobile grains."""
        d, m = ctypes.c_double(), ctypes.c_double()
        self._lib.sim_world_means(self._handle(), ctypes.byref(d), ctypes.byref(m))
        return d.value, m.value

    def momentum(self):
        px, py = ctypes.c_double(), ctypes.c_double()
        self._lib.sim_world_momentum(self._handle(), ctypes.byref(px), ctypes.byref(py))
        return px.value, py.value

    def removed_count(self, sink):
        return self._lib.sim_world_removed_count(self._handle(), sink)

    def surface_profile(self, x0, x1, bins):
        h = np.empty(bins)
        self._lib.sim_world_surface_profile(self._handle(), x0, x1, bins,
                                            _ptr(h, ctypes.c_double))
        return h

    # -------------------------------------------------------- editing

    def remove_rect(self, x0, y0, x1, y1):
        return self._lib.sim_world_remove_rect(self._handle(), x0, y0, x1, y1)

    def remove_ids(self, ids):
        ids = np.ascontiguousarray(ids, dtype=np.uint32)
        return self._lib.sim_world_remove_ids(self._handle(), _ptr(ids, ctypes.c_uint32),
                                              ids.size)

    def add_grains(self, grains=None, **arrays):
        """Add grains (Grains, dict or GrainBuffer, or x=, y=, radius=, ... arrays)."""
        if grains is None:
            grains = Grains(**arrays)
        elif isinstance(grains, dict):
            grains = Grains(**grains)
        elif isinstance(grains, GrainBuffer):
            grains = grains.grains()
        s = grains.grain_set()
        err = C.SimError()
        status = self._lib.sim_world_add_grains(self._handle(), ctypes.byref(s), ctypes.byref(err))
        if status != 0:
            _raise(err, "sim_world_add_grains")

    def freeze(self):
        self._lib.sim_world_freeze(self._handle())

    def wall_loads(self):
        """What the grains do to each wall in the last force evaluation (sim_world_wall_load):
        a list, one dict per wall in the definition's order, with fx, fy (N, the total force of
        the grains on it), normal (N, the sum of the contacts' normal forces, >= 0 pushing),
        tangential (N), torque (N m, about the wall's centre), length (m), stress (N/m, normal /
        length), x, y (m, its centre now), offset (m), speed (m/s) (a responding wall's motion
        along its axis, else 0) and contacts. Before the first step every force is 0."""
        loads = []
        load = C.SimWallLoad()
        while self._lib.sim_world_wall_load(self._handle(), len(loads), ctypes.byref(load)) == 0:
            d = {f[0]: getattr(load, f[0]) for f in C.SimWallLoad._fields_}
            d["stress"] = d["normal"] / d["length"] if d["length"] > 0 else 0.0
            loads.append(d)
        return loads

    # -------------------------------------------------------- files

    def save(self, path):
        """sim_world_save: the whole state (grains, walls, time, contact history, sink counts),
        written atomically; the `sablier` command reads it (sablier render, stage load)."""
        err = C.SimError()
        if self._lib.sim_world_save(self._handle(), C.as_bytes(path), ctypes.byref(err)) != 0:
            _raise(err, "sim_world_save %s" % os.fspath(path))
        return path

    def render(self, path, scene_name="python", seed=0, **style):
        """Write a figure of the current state (.png, .pdf, .svg) through libsablier-render
        (render_figure_write), or, when that library is not there, through `sablier render`.
        `style`: RenderStyle fields by name (width, height, color_by="force"|"speed"|
        "species"|"height"|"fixed", colormap="viridis"|"yellow_red"|"greys", force_chains,
        velocity_arrows, velocity_field, title, view=(x0, y0, x1, y1), ...)."""
        from . import render as _render
        return _render.figure(self, path, scene_name=scene_name, seed=seed, **style)
