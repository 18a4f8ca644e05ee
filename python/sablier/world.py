# SPDX-License-Identifier: MIT
"""Worlds: definitions, stepping, frame views as NumPy arrays, checkpoints, hashes."""
import ctypes
import os

import numpy as np

from . import _capi as C

# ------------------------------------------------------------------ errors


class SablierError(Exception):
    """A failure reported by the C library (SimError): status, field, step, grain."""

    def __init__(self, message, status=None, field="", step=-1, grain=-1):
        super().__init__(message)
        self.status = status
        self.field = field
        self.step = step
        self.grain = grain


class InvalidDefinition(SablierError, ValueError):
    """SIM_ERROR_INVALID: a bad definition (the CLI's exit status 2)."""


class Unstable(SablierError):
    """SIM_ERROR_UNSTABLE: the run blew up; the world is rolled back to the last good guard
    check, so World.save then saves the last good state (the CLI's exit status 1)."""


class StateIOError(SablierError, OSError):
    """SIM_ERROR_IO: a state file could not be read or written."""


class OutOfMemory(SablierError, MemoryError):
    """SIM_ERROR_MEMORY: the world cannot continue (only close() is left)."""


_ERRORS = {2: InvalidDefinition, 1: Unstable, 3: StateIOError, 4: OutOfMemory}


def _raise(err, what):
    message, field = C.error_text(err)
    cls = _ERRORS.get(err.status, SablierError)
    text = "%s: %s%s" % (what, field + ": " if field else "", message)
    raise cls(text, err.status, field, err.step, err.grain)


# ------------------------------------------------------------------ names

NORMAL = {"linear": 0, "hertz": 1}
TANGENTIAL = {"none": 0, "regularised": 1, "regularized": 1, "spring": 2}
ROLLING = {"off": 0, "none": 0, "chord": 1, "fixed": 2}
ONSET = {"step": 0, "event": 1}
DAMPING = {"gamma": 0, "restitution": 1, "critical": 2}
MASS = {"disk": 0, "sphere": 1}
SINK = {"below": 0, "above": 1, "left": 2, "right": 3, "rect": 4}


def _choice(table, value, what):
    if isinstance(value, str):
        try:
            return table[value]
        except KeyError:
            raise InvalidDefinition("%s: unknown %r (one of %s)" % (what, value, ", ".join(table)),
                                    2, what) from None
    return int(value)


def effects_bits(effects):
    """Effect names ("friction", "rolling_resistance", "periodic_x", "vibration", "fluid_drag",
    "removal") or an int of SimEffect bits -> bits."""
    if effects is None:
        return 0
    if isinstance(effects, int):
        return effects
    if isinstance(effects, str):
        effects = [effects]
    bits = 0
    lib = C.sim()
    for name in effects:
        bit = lib.sim_effect_from_name(name.encode())
        if not bit:
            raise InvalidDefinition("effects: unknown effect %r" % name, 2, "effects")
        bits |= bit
    return bits


def effects_names(bits):
    lib = C.sim()
    names = []
    for k in range(32):
        if bits & (1 << k):
            n = lib.sim_effect_name(1 << k)
            names.append(n.decode() if n else str(1 << k))
    return names


def material(**fields):
    """A SimMaterial: sim_material_default() with `fields` set (damping_mode may be a name:
    "gamma", "restitution", "critical"). Unknown field names are refused."""
    m = C.sim().sim_material_default()
    names = {f[0] for f in C.SimMaterial._fields_}
    for key, value in fields.items():
        if key not in names:
            raise InvalidDefinition("material: unknown field %r" % key, 2, key)
        if key == "damping_mode":
            value = _choice(DAMPING, value, "damping_mode")
        setattr(m, key, value)
    return m


# ------------------------------------------------------------------ arrays


def _array(values, dtype, count, name):
    a = np.ascontiguousarray(values, dtype=dtype)
    if a.ndim == 0:
        a = np.full(count, a, dtype=dtype)
    if a.shape != (count,):
        raise InvalidDefinition("grains.%s: %d values for %d grains" % (name, a.size, count), 2,
                                "grains." + name)
    return a


def _ptr(array, ctype):
    return array.ctypes.data_as(ctypes.POINTER(ctype))


class Grains:
    """Input grains as NumPy arrays (structure of arrays, as SimGrainSet). x, y, radius are
    required; the others may be None (zeros; species 0; flags 0; motion -1; ids 0..n-1).
    `fixed` (bool array) is a shorthand for flags = SIM_GRAIN_FIXED."""

    _DOUBLE = ("x", "y", "radius", "vx", "vy", "angle", "omega")

    def __init__(self, x, y, radius, vx=None, vy=None, angle=None, omega=None, species=None,
                 flags=None, motion=None, id=None, fixed=None):
        x = np.ascontiguousarray(x, dtype=np.float64)
        n = x.shape[0] if x.ndim else 1
        self.count = n
        self.x = _array(x, np.float64, n, "x")
        self.y = _array(y, np.float64, n, "y")
        self.radius = _array(radius, np.float64, n, "radius")
        for name, value in (("vx", vx), ("vy", vy), ("angle", angle), ("omega", omega)):
            setattr(self, name, None if value is None else _array(value, np.float64, n, name))
        self.species = None if species is None else _array(species, np.intc, n, "species")
        if fixed is not None:
            fixed_flags = np.where(_array(fixed, bool, n, "fixed"), C.SIM_GRAIN_FIXED, 0)
            flags = fixed_flags if flags is None else np.asarray(flags) | fixed_flags
        self.flags = None if flags is None else _array(flags, np.uintc, n, "flags")
        self.motion = None if motion is None else _array(motion, np.intc, n, "motion")
        self.id = None if id is None else _array(id, np.uint32, n, "id")

    def grain_set(self):
        """SimGrainSet pointing into these arrays (keep self alive while it is used)."""
        s = C.SimGrainSet()
        s.count = self.count
        for name in self._DOUBLE:
            a = getattr(self, name)
            if a is not None:
                setattr(s, name, _ptr(a, ctypes.c_double))
        if self.species is not None:
            s.species = _ptr(self.species, ctypes.c_int)
        if self.flags is not None:
            s.flags = _ptr(self.flags, ctypes.c_uint)
        if self.motion is not None:
            s.motion = _ptr(self.motion, ctypes.c_int)
        if self.id is not None:
            s.id = _ptr(self.id, ctypes.c_uint32)
        return s

    @classmethod
    def from_dict(cls, d):
        return cls(**d)


class GrainBuffer:
    """sim/sim.h's grain builders (rain-like lattice, rows and boxes of fixed grains) on a
    growable SimGrainBuffer owned by this object."""

    def __init__(self):
        self._b = C.SimGrainBuffer()
        C.sim().sim_grain_buffer_init(ctypes.byref(self._b))

    def __del__(self):
        if getattr(self, "_b", None) is not None:
            C.sim().sim_grain_buffer_free(ctypes.byref(self._b))
            self._b = None

    def __len__(self):
        return self._b.count

    def add(self, x, y, radius, species=0, fixed=False, motion=-1):
        flags = C.SIM_GRAIN_FIXED if fixed else 0
        return C.sim().sim_grain_buffer_add(ctypes.byref(self._b), x, y, radius, species, flags,
                                            motion)

    def fixed_row(self, x0, x1, y, radius, species=0, motion=-1):
        C.sim().sim_build_fixed_row(ctypes.byref(self._b), x0, x1, y, radius, species, motion)

    def fixed_column(self, x, y0, y1, radius, species=0, motion=-1):
        C.sim().sim_build_fixed_column(ctypes.byref(self._b), x, y0, y1, radius, species, motion)

    def fixed_box(self, x0, x1, y0, wall_top, radius, species=0):
        C.sim().sim_build_fixed_box(ctypes.byref(self._b), x0, x1, y0, wall_top, radius, species)

    def rain(self, seed, thesis000=None, **fields):
        """sim_build_rain with a SimRainDef: thesis000=(x0, x1, y0, y1, max_count) starts from
        sim_rain_def_thesis000, else from zeros; `fields` set SimRainDef fields. Returns the
        number of grains added."""
        lib = C.sim()
        if thesis000 is not None:
            rd = lib.sim_rain_def_thesis000(*thesis000)
        else:
            rd = C.SimRainDef()
        for key, value in fields.items():
            if key in ("species_fraction", "species_radius"):
                arr = getattr(rd, key)
                for k, v in enumerate(value):
                    arr[k] = v
            elif key in {f[0] for f in C.SimRainDef._fields_}:
                setattr(rd, key, value)
            else:
                raise InvalidDefinition("rain: unknown field %r" % key, 2, key)
        rng = C.SimRng()
        lib.sim_rng_seed(ctypes.byref(rng), seed)
        return lib.sim_build_rain(ctypes.byref(self._b), ctypes.byref(rd), ctypes.byref(rng))

    def grains(self):
        """The buffer's grains as a Grains of NumPy copies (edit them before building a world)."""
        b, n = self._b, self._b.count

        def cp(p, dtype):
            return np.ctypeslib.as_array(p, shape=(n,)).astype(dtype, copy=True) if n else \
                np.zeros(0, dtype)

        return Grains(x=cp(b.x, np.float64), y=cp(b.y, np.float64),
                      radius=cp(b.radius, np.float64), vx=cp(b.vx, np.float64),
                      vy=cp(b.vy, np.float64), angle=cp(b.angle, np.float64),
                      omega=cp(b.omega, np.float64), species=cp(b.species, np.intc),
                      flags=cp(b.flags, np.uintc), motion=cp(b.motion, np.intc),
                      id=cp(b.id, np.uint32))


# ------------------------------------------------------------------ definitions


class WorldDef:
    """A SimWorldDef (sim_world_def_default() to start) with Python-friendly setters, holding
    the arrays its pointers refer to. `raw` is the ctypes structure itself."""

    def __init__(self, raw=None, keep=None):
        self.raw = C.sim().sim_world_def_default() if raw is None else raw
        self._keep = list(keep or [])

    _SCALARS = {f[0] for f in C.SimWorldDef._fields_} - {
        "contact", "materials", "grains", "walls", "wall_count", "motions", "motion_count",
        "sinks", "sink_count", "body_force", "effects", "mass_model", "integrator",
        "species_count"}

    def set(self, **options):
        """Set definition fields by name; see World.from_arrays for the accepted keys."""
        r = self.raw
        for key, value in options.items():
            if value is None:
                continue
            if key == "effects":
                r.effects = effects_bits(value)
            elif key == "mass_model":
                r.mass_model = _choice(MASS, value, "mass_model")
            elif key == "integrator":
                if isinstance(value, str):
                    k = C.sim().sim_integrator_from_name(value.encode())
                    if k < 0:
                        raise InvalidDefinition("integrator: unknown %r" % value, 2, "integrator")
                    value = k
                r.integrator = int(value)
            elif key == "gravity":
                r.gravity_x, r.gravity_y = float(value[0]), float(value[1])
            elif key == "domain":
                r.domain_x0, r.domain_x1 = float(value[0]), float(value[1])
            elif key == "contact":
                self.set_contact(**value)
            elif key in ("normal", "tangential", "rolling", "clip_tensile", "onset"):
                self.set_contact(**{key: value})
            elif key == "materials":
                self.set_materials(value)
            elif key == "grains":
                self.set_grains(value)
            elif key == "walls":
                self.set_walls(value)
            elif key == "motions":
                self.set_motions(value)
            elif key == "sinks":
                self.set_sinks(value)
            elif key == "body_force":
                self.set_body_force(value)
            elif key in self._SCALARS:
                setattr(r, key, value)
            else:
                raise InvalidDefinition("world definition: unknown key %r" % key, 2, key)
        return self

    def set_contact(self, normal=None, tangential=None, rolling=None, clip_tensile=None,
                    onset=None):
        c = self.raw.contact
        if normal is not None:
            c.normal = _choice(NORMAL, normal, "contact.normal")
        if tangential is not None:
            c.tangential = _choice(TANGENTIAL, tangential, "contact.tangential")
        if rolling is not None:
            c.rolling = _choice(ROLLING, rolling, "contact.rolling")
        if clip_tensile is not None:
            c.clip_tensile = int(bool(clip_tensile))
        if onset is not None:
            c.onset = _choice(ONSET, onset, "contact.onset")

    def set_materials(self, materials):
        """A list (one per species) of SimMaterial or dicts of material() fields."""
        if len(materials) > C.SIM_MAX_SPECIES:
            raise InvalidDefinition("materials: at most %d species" % C.SIM_MAX_SPECIES, 2,
                                    "species_count")
        for k, m in enumerate(materials):
            self.raw.materials[k] = m if isinstance(m, C.SimMaterial) else material(**m)
        self.raw.species_count = len(materials)

    def set_grains(self, grains):
        if isinstance(grains, GrainBuffer):
            grains = grains.grains()
        elif isinstance(grains, dict):
            grains = Grains(**grains)
        self._grains = grains
        self.raw.grains = grains.grain_set()

    def set_walls(self, walls):
        """Walls as (x0, y0, x1, y1[, species[, motion]]) tuples or SimWall."""
        n = len(walls)
        arr = (C.SimWall * max(n, 1))()
        for k, w in enumerate(walls):
            if isinstance(w, C.SimWall):
                arr[k] = w
            else:
                w = tuple(w)
                arr[k] = C.SimWall(*[float(v) for v in w[:4]],
                                   int(w[4]) if len(w) > 4 else 0,
                                   int(w[5]) if len(w) > 5 else -1)
        self._walls = arr
        self.raw.wall_count = n
        self.raw.walls = ctypes.cast(arr, ctypes.POINTER(C.SimWall)) if n else None

    def set_motions(self, motions):
        """Motions as dicts (amplitude, frequency, phase, direction=(dx, dy)) or SimMotion."""
        if len(motions) > C.SIM_MAX_MOTIONS:
            raise InvalidDefinition("motions: at most %d" % C.SIM_MAX_MOTIONS, 2, "motion_count")
        for k, m in enumerate(motions):
            if not isinstance(m, C.SimMotion):
                d = m.get("direction", (0.0, 1.0))
                m = C.SimMotion(m.get("amplitude", 0.0), m.get("frequency", 0.0),
                                m.get("phase", 0.0), d[0], d[1])
            self.raw.motions[k] = m
        self.raw.motion_count = len(motions)

    def set_sinks(self, sinks):
        """Sinks as dicts (shape name, level or x0, y0, x1, y1) or SimSink."""
        if len(sinks) > C.SIM_MAX_SINKS:
            raise InvalidDefinition("sinks: at most %d" % C.SIM_MAX_SINKS, 2, "sink_count")
        for k, s in enumerate(sinks):
            if not isinstance(s, C.SimSink):
                s = C.SimSink(_choice(SINK, s.get("shape", "below"), "sink.shape"),
                              s.get("level", 0.0), s.get("x0", 0.0), s.get("y0", 0.0),
                              s.get("x1", 0.0), s.get("y1", 0.0))
            self.raw.sinks[k] = s
        self.raw.sink_count = len(sinks)

    def set_body_force(self, fn):
        """A Python body-force stage fn(view) (effect fluid_drag): view.x, .y, .vx, .vy,
        .radius, .mass are read-only arrays of the mobile grains and view.fx, view.fy writable
        arrays to add forces to; view.time in s. Called at every force evaluation (slow: for
        prototypes). An exception stops the next step() with that exception."""
        holder = _BodyForce(fn)
        self._body = holder
        self.raw.body_force = C.SimBodyForce(holder.c_fn, None)

    def validate(self):
        err = C.SimError()
        if C.sim().sim_world_def_validate(ctypes.byref(self.raw), ctypes.byref(err)) != 0:
            _raise(err, "invalid definition")

    def timing(self):
        t = C.sim().sim_world_def_timing(ctypes.byref(self.raw))
        return {f[0]: getattr(t, f[0]) for f in C.SimTiming._fields_}


class BodyForceView:
    def __init__(self, v):
        n = v.count
        self.count = n
        self.time = v.time
        for name in ("x", "y", "vx", "vy", "radius", "mass"):
            a = np.ctypeslib.as_array(getattr(v, name), shape=(n,)) if n else np.zeros(0)
            a.flags.writeable = False
            setattr(self, name, a)
        self.fx = np.ctypeslib.as_array(v.fx, shape=(n,)) if n else np.zeros(0)
        self.fy = np.ctypeslib.as_array(v.fy, shape=(n,)) if n else np.zeros(0)


class _BodyForce:
    def __init__(self, fn):
        self.fn = fn
        self.error = None

        def apply(_context, view):
            if self.error is not None:
                return
            try:
                fn(BodyForceView(view.contents))
            except BaseException as e:  # noqa: B902 - reported after the step
                self.error = e

        self.c_fn = C.BODY_FORCE_FN(apply)


# ------------------------------------------------------------------ frames


class Frame:
    """A view of the world's state: NumPy arrays over the C library's own memory (no copies),
    in frame order (mobile grains first, then fixed grains; the order changes at neighbour-list
    builds: follow grains by `id`). Valid until the next call that changes the world (step,
    frame, energy and other diagnostics, edits, close): afterwards its arrays read freed or reused
    memory. Take `copy()` to keep values.

    Arrays: x, y, angle, radius, vx, vy, omega, species, flags, id, force (sum of contact-force
    magnitudes), fx, fy, torque; `contacts` is a structured array with fields i, j (j = -1 -
    wall index for a wall contact), normal_force, tangential_force, overlap, x, y; `walls` has
    x0, y0, x1, y1, species, motion. Scalars: count, mobile_count, step, time, time_scale,
    periodic, domain_x0, domain_x1."""

    _ARRAYS = (("x", np.float64), ("y", np.float64), ("angle", np.float64),
               ("radius", np.float64), ("vx", np.float64), ("vy", np.float64),
               ("omega", np.float64), ("species", np.intc), ("flags", np.uintc),
               ("id", np.uint32), ("force", np.float64), ("fx", np.float64), ("fy", np.float64),
               ("torque", np.float64))
    CONTACT_DTYPE = np.dtype({"names": ["i", "j", "normal_force", "tangential_force", "overlap",
                                        "x", "y"],
                              "formats": [np.intc, np.intc] + [np.float64] * 5,
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
        from .scene import Scene
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
                from .scene import Scene
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
