# SPDX-License-Identifier: MIT
"""World definitions (SimWorldDef), grain sets, material tables and the errors of the C API."""
import ctypes
import math
import warnings

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


def _scene_table(group, k=0):
    """A key table of the scene loader (scene_keys in app/scene/scene.h): the lists scene files are
    checked against, read here so that Python and scene files accept the same keys."""
    lib = C.scene()
    if lib is None:
        raise OSError("sablier: libsablier-scene.so not found: it holds the scene keys")
    p = lib.scene_keys(group.encode(), k)
    out = []
    while p and p[len(out)] is not None:
        out.append(p[len(out)].decode())
    return out


# one way of giving normal damping each (docs/scenes.md, species)
_DAMPING_KEYS = {"gamma_n": "gamma", "restitution": "restitution",
                 "critical_fraction": "critical"}


def _material_keys(fields):
    """fields with the SimMaterial names of older versions (normal_stiffness, friction, ...)
    turned into the scene keys (k_n, mu, ...), with a DeprecationWarning each."""
    struct_names = _scene_table("material", 0)
    scene_names = _scene_table("material", 1)
    out = {}
    for key, value in fields.items():
        if key not in scene_names and key in struct_names:
            new = scene_names[struct_names.index(key)]
            warnings.warn("material key %r is deprecated: use the scene key %r" % (key, new),
                          DeprecationWarning, stacklevel=3)
            key = new
        out[key] = value
    return out


def material(**fields):
    """A SimMaterial from the keys of a scene file's species (docs/scenes.md): density, k_n,
    gamma_n | restitution | critical_fraction (at most one; none: elastic, gamma_n = 0), mu,
    gamma_s, k_t, mu_r, k_r; `name` is accepted and ignored. Unset keys take the scene
    loader's defaults (scene_material_default). An unknown key raises InvalidDefinition naming
    it. The SimMaterial names of older versions (normal_stiffness, friction, normal_damping,
    ...) and damping_mode still work, with a DeprecationWarning."""
    lib = C.scene()
    if lib is None:
        raise OSError("sablier: libsablier-scene.so not found: it holds the material defaults")
    m = lib.scene_material_default()
    mode = fields.pop("damping_mode", None)
    if mode is not None:
        warnings.warn("material key 'damping_mode' is deprecated: give one of gamma_n, "
                      "restitution, critical_fraction", DeprecationWarning, stacklevel=2)
    fields = _material_keys(fields)
    allowed = _scene_table("species")
    struct_of = dict(zip(_scene_table("material", 1), _scene_table("material", 0)))
    for key in fields:
        if key not in allowed:
            raise InvalidDefinition("material: unknown key `%s` (keys: %s)"
                                    % (key, ", ".join(allowed)), 2, key)
    ways = [k for k in _DAMPING_KEYS if k in fields]
    if len(ways) > 1 and mode is None:
        raise InvalidDefinition("material: give only one of gamma_n, restitution, "
                                "critical_fraction (got %s)" % ", ".join(ways), 2, ways[1])
    for key, value in fields.items():
        if key == "name":
            continue
        value = float(value)
        positive = key in ("density", "k_n", "gamma_s", "k_t", "k_r")
        if not np.isfinite(value) or value < 0 or (positive and value == 0):
            raise InvalidDefinition("material: `%s` must be %s (got %g)" % (
                key, "positive" if positive else "non-negative", value), 2, key)
        if key == "restitution" and not 0 < value <= 1:
            raise InvalidDefinition("material: `restitution` must be in (0, 1] (got %g)"
                                    % value, 2, key)
        setattr(m, struct_of[key], value)
    if ways and mode is None:
        m.damping_mode = DAMPING[_DAMPING_KEYS[ways[0]]]
    if mode is not None:
        m.damping_mode = _choice(DAMPING, mode, "damping_mode")
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
        self.motion_names = []

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
        """A list (one per species) of SimMaterial or dicts of material() keys (a scene's
        species keys: density, k_n, restitution, mu, ...)."""
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
        """Motions as in a scene file's `motions` group (docs/scenes.md): a dict name -> dict,
        or a list of dicts (each may hold "name"), or SimMotion. Keys: kind ("sinusoidal"
        default, "velocity", "rotation", "compose"), the kind's own (sinusoidal: amplitude m,
        frequency Hz, phase rad, direction; velocity: velocity m/s; rotation: center m,
        angular_velocity rad/s; compose: of = names or indices of motions above), and start,
        ramp, stop (s). Checked as the scene loader does: an unknown key raises
        InvalidDefinition naming it."""
        if isinstance(motions, dict):
            motions = [dict(m, name=name) if isinstance(m, dict) else m
                       for name, m in motions.items()]
        if len(motions) > C.SIM_MAX_MOTIONS:
            raise InvalidDefinition("motions: at most %d" % C.SIM_MAX_MOTIONS, 2, "motion_count")
        names = []
        for k, m in enumerate(motions):
            if not isinstance(m, C.SimMotion):
                m = _motion(m, k, names)
            else:
                names.append("motion%d" % k)
            self.raw.motions[k] = m
        self.raw.motion_count = len(motions)
        self.motion_names = names

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


def _number(d, key, what, default=None, check=None):
    if key not in d:
        if default is None:
            raise InvalidDefinition("%s: `%s` is missing" % (what, key), 2, key)
        return default
    value = float(d[key])
    if not math.isfinite(value) or (check is not None and not check(value)):
        raise InvalidDefinition("%s: `%s` = %r is out of range" % (what, key, d[key]), 2, key)
    return value


def _vector(d, key, what, default=None):
    if key not in d:
        if default is None:
            raise InvalidDefinition("%s: `%s` is missing" % (what, key), 2, key)
        return default
    v = [float(x) for x in d[key]]
    if len(v) != 2 or not all(math.isfinite(x) for x in v):
        raise InvalidDefinition("%s: `%s` must be two finite numbers" % (what, key), 2, key)
    return v


def _motion(d, k, names):
    """A SimMotion from a scene-style dict (the scene loader's tables and checks)."""
    d = dict(d)
    name = str(d.pop("name", "motion%d" % k))
    what = "motion `%s`" % name
    kinds = _scene_table("motion.kinds")
    kind_name = d.get("kind", kinds[0])
    if kind_name not in kinds:
        raise InvalidDefinition("%s: `kind` = %r is not one of %s" % (what, kind_name,
                                                                     ", ".join(kinds)), 2, "kind")
    kind = kinds.index(kind_name)
    allowed = _scene_table("motion", kind) + _scene_table("motion.schedule")
    for key in d:
        if key not in allowed:
            raise InvalidDefinition("unknown key `%s` in %s (keys: %s)"
                                    % (key, what, ", ".join(allowed)), 2, key)
    m = C.SimMotion()
    m.kind = kind
    if kind == 0:
        m.amplitude = _number(d, "amplitude", what, check=lambda v: v >= 0)
        m.frequency = _number(d, "frequency", what, check=lambda v: v > 0)
        m.phase = _number(d, "phase", what, 0.0)
        dx, dy = _vector(d, "direction", what, [0.0, 1.0])
        norm = math.hypot(dx, dy)
        if not norm > 0:
            raise InvalidDefinition("%s: `direction` must not be zero" % what, 2, "direction")
        m.direction_x, m.direction_y = dx / norm, dy / norm
    elif kind == 1:
        m.velocity_x, m.velocity_y = _vector(d, "velocity", what)
    elif kind == 2:
        m.center_x, m.center_y = _vector(d, "center", what)
        m.angular_velocity = _number(d, "angular_velocity", what)
    else:
        parts = d.get("of")
        if not parts or len(parts) > 4:
            raise InvalidDefinition("%s: `of` must list 1 to 4 motions above this one" % what,
                                    2, "of")
        for j, p in enumerate(parts):
            index = names.index(p) if isinstance(p, str) and p in names else \
                (p if isinstance(p, int) and 0 <= p < k else -1)
            if index < 0:
                raise InvalidDefinition("%s: `of`: `%s` is not a motion defined above this one"
                                        % (what, p), 2, "of")
            m.parts[j] = index
        m.part_count = len(parts)
    m.start = _number(d, "start", what, 0.0, lambda v: v >= 0)
    m.ramp = _number(d, "ramp", what, 0.0, lambda v: v >= 0)
    m.stop = _number(d, "stop", what, 0.0)
    if "stop" in d and not m.stop > m.start:
        raise InvalidDefinition("%s: `stop` = %g must be after `start` = %g"
                                % (what, m.stop, m.start), 2, "stop")
    if kind == 3 and m.ramp > 0:
        raise InvalidDefinition("%s: a composition has no `ramp` of its own: ramp its parts"
                                % what, 2, "ramp")
    names.append(name)
    return m


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
