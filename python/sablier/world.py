# SPDX-License-Identifier: MIT
"""Worlds: stepping, frame views as NumPy arrays, checkpoints, hashes (definitions: definition.py)."""
import ctypes
import os

import numpy as np

from . import _capi as C
from .definition import (GrainBuffer, Grains, InvalidDefinition, OutOfMemory, StateIOError,
                         WorldDef, _array, _ptr, _raise, effects_names)
from .scene import Scene


class StateNotFound(StateIOError, FileNotFoundError):
    """World.from_state of a path where no file is (a StateIOError and a FileNotFoundError)."""


class StaleFrame(RuntimeError):
    """A Frame view read after its world changed (docs/python.md, "Frames")."""


class Frame:
    """A view of the world's state: NumPy arrays over the C library's own memory (no copies),
    in frame order (mobile grains first, then fixed grains; the order changes at neighbour-list
    builds: follow grains by `id`). Valid until the next call that changes the world (step,
    frame, energy and other diagnostics, edits, close): reading an array of the Frame after that
    raises StaleFrame (the world counts its changes). An array taken out of the Frame
    (`x = f.x`) is a bare NumPy view that cannot check: use it before the next change, or keep
    `copy()` (or world.frame(copy=True)) to hold values.

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
        self._generation = owner._generation if owner is not None else None
        n = raw.count
        for name in ("count", "mobile_count", "step", "time", "time_scale", "periodic",
                     "domain_x0", "domain_x1"):
            setattr(self, name, getattr(raw, name))
        data = {}
        for name, dtype in self._ARRAYS:
            p = getattr(raw, name)
            if n and p:
                a = np.ctypeslib.as_array(p, shape=(n,))
                a.flags.writeable = False
            else:
                a = np.zeros(n if not p else 0, dtype)
            data[name] = a
        data["contacts"] = self._records(raw.contacts, raw.contact_count, C.SimContact,
                                         self.CONTACT_DTYPE)
        data["walls"] = self._records(raw.walls, raw.wall_count, C.SimWall, self.WALL_DTYPE)
        self._data = data

    def __getattr__(self, name):
        data = self.__dict__.get("_data")
        if data is None or name not in data:
            raise AttributeError(name)
        owner = self.__dict__.get("_owner")
        if owner is not None and owner._generation != self._generation:
            raise StaleFrame("sablier: this Frame of step %d is stale: the world has changed "
                             "since (step, edit, frame or diagnostics); take world.frame() again "
                             "or keep frame.copy()" % self.step)
        return data[name]

    @property
    def stale(self):
        """True once the world changed after this view was taken (its arrays then refuse to be
        read; copies never go stale)."""
        return self._owner is not None and self._owner._generation != self._generation

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
        f._generation = None
        for name in ("count", "mobile_count", "step", "time", "time_scale", "periodic",
                     "domain_x0", "domain_x1"):
            setattr(f, name, getattr(self, name))
        f._data = {name: getattr(self, name).copy() for name in self._data}
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
        self._generation = 0
        self._borrowed = False
        self._gravity = (definition.raw.gravity_x, definition.raw.gravity_y) \
            if definition is not None else None

    @classmethod
    def _borrow(cls, handle, definition=None):
        """A World over a handle owned elsewhere (the stage runner's world, valid inside a
        callback only); close() forgets it without destroying it."""
        world = cls(definition, _handle=handle)
        world._borrowed = True
        return world

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
        if not os.path.isfile(path):
            raise StateNotFound("sablier: no state file %s" % os.fspath(path), 3, "path")
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
            if not self._borrowed:
                self._lib.sim_world_destroy(self._w)
            self._w = None
            self._generation += 1

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _moving(self):
        """The handle, after counting a change: Frames taken before go stale."""
        w = self._handle()
        self._generation += 1
        return w

    def _handle(self):
        if not self._w:
            raise ValueError("world is closed" if not self._borrowed else
                             "the stage runner's world is valid inside its callback only")
        if self._dead:
            raise OutOfMemory("world ran out of memory earlier (%s); only close() is left"
                              % self._dead, 4)
        return self._w

    # -------------------------------------------------------- stepping

    def step(self, steps=1):
        """Advance by `steps` time steps. Raises Unstable (rolled back to the last good state),
        OutOfMemory; ValueError for a negative count. Invalidates earlier Frame views."""
        steps = int(steps)
        if steps < 0:
            raise ValueError("step(%d): the step count must be >= 0" % steps)
        w = self._moving()
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

    def frame(self, copy=False):
        """A Frame: zero-copy NumPy views valid until the next call that changes the world
        (afterwards reading them raises StaleFrame); copy=True: NumPy copies, valid for ever."""
        self._lib.sim_world_frame(self._moving(), ctypes.byref(self._frame))
        f = Frame(self._frame, self)
        return f.copy() if copy else f

    def hash(self):
        """sim_world_hash: FNV-1a of positions, velocities and angles of all grains (the value
        the C tests and tools print; equal hashes = the same bits)."""
        return int(self._lib.sim_world_hash(self._handle()))

    def energy(self):
        """dict of SimEnergy: kinetic, potential, rotational, elastic, total (J), mobile,
        contacts."""
        e = self._lib.sim_world_energy(self._moving())
        return {f[0]: getattr(e, f[0]) for f in C.SimEnergy._fields_}

    def coordination(self):
        return self._lib.sim_world_coordination(self._moving())

    def packing_fraction(self, x0, y0, x1, y1):
        return self._lib.sim_world_packing_fraction(self._handle(), x0, y0, x1, y1)

    def max_overlap_ratio(self):
        return self._lib.sim_world_max_overlap_ratio(self._moving())

    def hexatic_order(self):
        return self._lib.sim_world_hexatic_order(self._moving())

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
        return self._lib.sim_world_remove_rect(self._moving(), x0, y0, x1, y1)

    def remove_ids(self, ids):
        ids = np.ascontiguousarray(ids, dtype=np.uint32)
        return self._lib.sim_world_remove_ids(self._moving(), _ptr(ids, ctypes.c_uint32),
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
        status = self._lib.sim_world_add_grains(self._moving(), ctypes.byref(s), ctypes.byref(err))
        if status != 0:
            _raise(err, "sim_world_add_grains")

    def freeze(self):
        self._lib.sim_world_freeze(self._moving())

    def set_grains(self, ids=None, *, x=None, y=None, vx=None, vy=None, angle=None,
                   omega=None, radius=None, fixed=None):
        """Write grains in place between steps (sim_world_set_grains): `ids` are stable ids
        (None: every grain, values in frame order); x and y (m) together, vx and vy (m/s)
        together, angle (rad), omega (rad/s), radius (m: mass and inertia follow), fixed
        (bool: a grain made fixed stops where it is; the frame order then changes). Scalars
        are broadcast. The forces are evaluated anew and the integrator restarts. Raises
        InvalidDefinition (nothing changed) for an unknown id, a value that is not finite, a
        radius <= 0 or a radius whose contact time the time step no longer resolves."""
        w = self._handle()
        if ids is None:
            n = self.grain_count
            id_arr = None
        else:
            id_arr = np.atleast_1d(np.ascontiguousarray(ids, dtype=np.uint32))
            n = id_arr.size
        values = {}
        s = C.SimGrainSet()
        s.count = n
        for name, value in (("x", x), ("y", y), ("vx", vx), ("vy", vy), ("angle", angle),
                            ("omega", omega), ("radius", radius)):
            if value is not None:
                values[name] = _array(value, np.float64, n, name)
                setattr(s, name, _ptr(values[name], ctypes.c_double))
        if fixed is not None:
            values["flags"] = np.where(_array(fixed, bool, n, "fixed"), C.SIM_GRAIN_FIXED,
                                       0).astype(np.uintc)
            s.flags = _ptr(values["flags"], ctypes.c_uint)
        if id_arr is not None:
            s.id = _ptr(id_arr, ctypes.c_uint32)
        err = C.SimError()
        self._generation += 1
        if self._lib.sim_world_set_grains(w, ctypes.byref(s), ctypes.byref(err)) != 0:
            if err.status == 4:
                self._dead = C.error_text(err)[0]
            _raise(err, "set_grains")
        return self

    def set_positions(self, x, y, ids=None):
        """Centres (m) of the grains `ids` (None: all, frame order)."""
        return self.set_grains(ids, x=x, y=y)

    def set_velocities(self, vx, vy, ids=None):
        """Velocities (m/s) of mobile grains `ids` (None: all, frame order; fixed ignore it)."""
        return self.set_grains(ids, vx=vx, vy=vy)

    def set_radii(self, radius, ids=None):
        """Radii (m) of grains `ids`; masses and moments of inertia follow."""
        return self.set_grains(ids, radius=radius)

    def set_fixed(self, fixed, ids=None):
        """Make grains `ids` fixed (True) or mobile (False)."""
        return self.set_grains(ids, fixed=fixed)

    @property
    def gravity(self):
        """(g_x, g_y), m/s^2, as last set (None for a stage runner's world not yet set)."""
        return self._gravity

    @gravity.setter
    def gravity(self, value):
        gx, gy = float(value[0]), float(value[1])
        if not (np.isfinite(gx) and np.isfinite(gy)):
            raise InvalidDefinition("gravity: (%r, %r) is not finite" % (gx, gy), 2, "gravity")
        self._lib.sim_world_set_gravity(self._moving(), gx, gy)
        self._gravity = (gx, gy)

    def set_motion(self, motion, on=0.0, off=float("inf")):
        """Schedule motion `motion` (index, or name for a world with named motions) by world
        time (sim_world_set_motion): it runs on its own clock from t = on (s) and holds its
        pose from t = off on; on=inf: never enabled."""
        names = getattr(self.definition, "motion_names", None) or []
        if isinstance(motion, str):
            if motion not in names:
                raise InvalidDefinition("set_motion: no motion named %r (motions: %s)"
                                        % (motion, ", ".join(names) or "none"), 2, "motions")
            motion = names.index(motion)
        count = self.definition.raw.motion_count if self.definition is not None else \
            C.SIM_MAX_MOTIONS
        if not 0 <= int(motion) < count:
            raise InvalidDefinition("set_motion: motion %d out of range (%d motions)"
                                    % (motion, count), 2, "motions")
        self._lib.sim_world_set_motion(self._moving(), int(motion), float(on), float(off))

    def masses(self):
        """Masses of the grains in frame order, kg."""
        m = np.empty(self.grain_count)
        self._lib.sim_world_masses(self._handle(), _ptr(m, ctypes.c_double))
        return m

    def coarse(self, fields=("phi", "rho", "vx", "vy", "sxx", "sxy", "syy", "p"), *,
               geometry="grid", box=None, cell=None, width=None, kernel="lucy",
               normalise=True):
        """Coarse-grained continuum fields of the present state (sim/coarse.c, Weinhart et al.
        2012) as NumPy arrays: a dict of field name -> array, plus "x" and "y" (node
        coordinates, m). geometry "grid": arrays of shape (ny, nx) over `box` = (x0, y0, x1,
        y1) (default: the grains' box) with square cells of side `cell` (default: the mean
        diameter); "profile_y"/"profile_x": 1D profiles along y/x averaged across the box.
        width: the kernel's cutoff radius (default 2 cell); kernel "lucy" or "gaussian".
        Fields: phi, rho (kg/m^2), jx, jy, vx, vy (m/s), T, kxx..kyy, cxx..cyy, sxx..syy (N/m,
        compression positive), p, z, fxx, fxy, fyy (sim.h SimCoarseField). One sample."""
        lib = self._lib
        codes = []
        for name in fields:
            k = lib.sim_coarse_field_from_name(name.encode())
            if k < 0:
                raise InvalidDefinition("coarse: unknown field %r" % name, 2, "fields")
            codes.append(k)
        geometries = {"grid": 0, "profile_y": 1, "profile_x": 2}
        if geometry not in geometries:
            raise InvalidDefinition("coarse: unknown geometry %r (one of %s)"
                                    % (geometry, ", ".join(geometries)), 2, "geometry")
        if kernel not in ("lucy", "gaussian"):
            raise InvalidDefinition("coarse: unknown kernel %r" % kernel, 2, "kernel")
        f = self.frame()
        if cell is None:
            mobile = f.radius[:f.mobile_count]
            cell = 2.0 * float(mobile.mean()) if mobile.size else 1.0
        if box is None:
            r = f.radius
            box = (float((f.x - r).min()), float((f.y - r).min()), float((f.x + r).max()),
                   float((f.y + r).max())) if f.count else (0.0, 0.0, 1.0, 1.0)
        x0, y0, x1, y1 = (float(v) for v in box)
        d = lib.sim_coarse_def_default()
        d.kernel = 0 if kernel == "lucy" else 1
        d.width = float(width) if width is not None else 2.0 * cell
        d.geometry = geometries[geometry]
        d.x0, d.y0, d.x1, d.y1 = x0, y0, x1, y1
        d.cell_x = d.cell_y = float(cell)
        d.nx = max(1, int(np.ceil((x1 - x0) / cell)))
        d.ny = max(1, int(np.ceil((y1 - y0) / cell)))
        if geometry == "profile_y":
            d.nx = 1
        elif geometry == "profile_x":
            d.ny = 1
        d.contacts = int(any(lib.sim_coarse_field_needs_contacts(k) for k in codes))
        d.normalise = int(bool(normalise))
        err = C.SimError()
        cg = lib.sim_coarse_create(ctypes.byref(d), ctypes.byref(err))
        if not cg:
            _raise(err, "coarse")
        try:
            mass = self.masses()
            if lib.sim_coarse_add(cg, ctypes.byref(self._frame), _ptr(mass, ctypes.c_double),
                                  0.0, 0.0) != 0:
                raise OutOfMemory("coarse: out of memory", 4)
            n = lib.sim_coarse_nodes(cg)
            shape = (d.ny, d.nx) if geometry == "grid" else (n,)
            out = {}
            xs, ys = np.empty(n), np.empty(n)
            px, py = ctypes.c_double(), ctypes.c_double()
            for k in range(n):
                lib.sim_coarse_node(cg, k, ctypes.byref(px), ctypes.byref(py))
                xs[k], ys[k] = px.value, py.value
            out["x"], out["y"] = xs.reshape(shape), ys.reshape(shape)
            for name, code in zip(fields, codes):
                a = np.empty(n)
                lib.sim_coarse_field(cg, code, _ptr(a, ctypes.c_double))
                out[name] = a.reshape(shape)
            return out
        finally:
            lib.sim_coarse_destroy(cg)

    def wall_loads(self):
        """What the grains do to each wall in the last force evaluation (sim_world_wall_load):
        a list, one dict per wall in the definition's order, with fx, fy (N, the total force of
        the grains on it), normal (N, the sum of the contacts' normal forces, >= 0 pushing),
        tangential (N), torque (N m, about the wall's centre), length (m), stress (N/m, normal /
        length), x, y (m, its centre now), offset (m), speed (m/s) (a responding wall's motion
        along its axis, else 0), contacts, servo_flips (a servo's steps spent flipping between
        +-max_speed, sim.h SimWallLoad) and servo_flip_time (s, NaN: never). Before the first
        step every force is 0."""
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
        if self._lib.sim_world_save(self._moving(), C.as_bytes(path), ctypes.byref(err)) != 0:
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
