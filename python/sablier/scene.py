# SPDX-License-Identifier: MIT
"""Scene files through the C scene loader (libsablier-scene: app/scene/scene.h)."""
import ctypes
import errno
import os

from . import _capi as C
from .definition import InvalidDefinition, WorldDef


def _sets_list(sets):
    """{"key": value} or ["key=value", ...] -> ["key=value", ...]; booleans as true/false."""
    if sets is None:
        return []
    if isinstance(sets, dict):
        out = []
        for k, v in sets.items():
            if isinstance(v, bool):
                v = "true" if v else "false"
            elif isinstance(v, (list, tuple)):
                v = "[" + ", ".join(repr(float(x)) if isinstance(x, (int, float)) else
                                    '"%s"' % x for x in v) + "]"
            out.append("%s=%s" % (k, v))
        return out
    return list(sets)


class Scene:
    """A loaded and checked scene (scene_load with --set overrides). Attributes: path, name,
    seed, species_names, motion_names, stage_names, stage_count; world_def(stage) gives the
    stage's SimWorldDef (its pointers into this scene stay valid while the Scene lives; the
    WorldDef keeps the Scene alive)."""

    def __init__(self, path, sets=None):
        lib = C.scene()
        if lib is None:
            raise OSError("sablier: libsablier-scene.so not found: scene files need the scene "
                          "loader library (or run whole scenes with sablier.run)")
        self._lib = lib
        if not os.path.isfile(path):
            raise FileNotFoundError(errno.ENOENT, "sablier: no scene file", os.fspath(path))
        items = _sets_list(sets)
        arr = (ctypes.c_char_p * max(len(items), 1))(*[s.encode() for s in items])
        err = ctypes.create_string_buffer(1024)
        p = lib.scene_load(C.as_bytes(path), arr, len(items), err, len(err))
        if not p:
            raise InvalidDefinition(err.value.decode("utf-8", "replace"), 2, "")
        self._p = p
        s = p.contents
        self.path = os.fsdecode(s.path)
        self.name = s.name.decode()
        self.seed = int(s.seed)
        d = getattr(s, "def")  # `def` is a Python keyword
        self.species_names = [s.species_names[k].value.decode() for k in range(d.species_count)]
        self.motion_names = [s.motion_names[k].value.decode() for k in range(d.motion_count)]
        self.stage_count = s.stage_count
        self.stage_names = [s.stages[k].name.decode() for k in range(s.stage_count)]
        self.stages = [{"name": st.name.decode(), "duration": st.duration,
                        "time_step": st.time_step, "skip": bool(st.skip), "movie": bool(st.movie),
                        "load": ("scene", "previous", "file")[st.load],
                        "load_path": os.fsdecode(st.load_path)}
                       for st in (s.stages[k] for k in range(s.stage_count))]

    def close(self):
        if getattr(self, "_p", None):
            self._lib.scene_free(self._p)
            self._p = None

    def __del__(self):
        self.close()

    def stage_index(self, stage):
        if isinstance(stage, str):
            k = self._lib.scene_stage_index(self._p, stage.encode())
            if k < 0:
                raise InvalidDefinition("%s: no stage %r (stages: %s)" % (
                    self.path, stage, ", ".join(self.stage_names)), 2, "stages")
            return k
        if not 0 <= stage < self.stage_count:
            raise InvalidDefinition("%s: stage %d out of range" % (self.path, stage), 2,
                                    "stages")
        return int(stage)

    def world_def(self, stage=0):
        """The stage's world definition (scene_world_def), as a WorldDef."""
        if not self._p:
            raise ValueError("scene is closed")
        raw = self._lib.scene_world_def(self._p, self.stage_index(stage))
        d = WorldDef(raw, keep=[self])
        d.motion_names = list(self.motion_names)
        return d
