# SPDX-License-Identifier: MIT
"""ctypes mirror of sablier's public C headers (sim/sim.h, render/render.h, app/scene/scene.h).

Every Structure below copies the field order and types of its C struct. tests/python/test_abi.py
compiles a probe against the real headers and checks sizeof and every offsetof, so a change of a
header that is not mirrored here fails the tests instead of corrupting memory.
"""
import os
from ctypes import (CFUNCTYPE, POINTER, Structure, c_char, c_char_p, c_double, c_int, c_long,
                    c_uint, c_uint32, c_uint64, c_void_p, c_size_t)

from . import _loader

SIM_MAX_SPECIES = 8
SIM_MAX_MOTIONS = 8
SIM_MAX_SINKS = 16
SIM_GRAIN_FIXED = 1

_pd = POINTER(c_double)
_pi = POINTER(c_int)
_pu = POINTER(c_uint)
_pu32 = POINTER(c_uint32)

# ------------------------------------------------------------------ sim/sim.h


class SimMaterial(Structure):
    _fields_ = [("density", c_double), ("normal_stiffness", c_double), ("damping_mode", c_int),
                ("normal_damping", c_double), ("restitution", c_double),
                ("critical_fraction", c_double), ("friction", c_double),
                ("tangential_damping", c_double), ("tangential_stiffness", c_double),
                ("rolling_friction", c_double), ("rolling_stiffness", c_double),
                ("spring_damping", c_double)]


class SimContactModel(Structure):
    _fields_ = [("normal", c_int), ("tangential", c_int), ("rolling", c_int),
                ("clip_tensile", c_int),
                ("onset", c_int)]


class SimGrainSet(Structure):
    _fields_ = [("count", c_int), ("x", _pd), ("y", _pd), ("radius", _pd), ("vx", _pd),
                ("vy", _pd), ("angle", _pd), ("omega", _pd), ("species", _pi), ("flags", _pu),
                ("motion", _pi), ("id", _pu32)]


class SimMotion(Structure):
    _fields_ = [("amplitude", c_double), ("frequency", c_double), ("phase", c_double),
                ("direction_x", c_double), ("direction_y", c_double), ("kind", c_int),
                ("velocity_x", c_double), ("velocity_y", c_double), ("center_x", c_double),
                ("center_y", c_double), ("angular_velocity", c_double), ("start", c_double),
                ("ramp", c_double), ("stop", c_double), ("part_count", c_int),
                ("parts", c_int * 4)]


class SimWall(Structure):
    _fields_ = [("x0", c_double), ("y0", c_double), ("x1", c_double), ("y1", c_double),
                ("species", c_int), ("motion", c_int), ("shape", c_int), ("side", c_int),
                ("center_x", c_double), ("center_y", c_double), ("radius", c_double),
                ("angle0", c_double), ("angle1", c_double)]


class SimWallLoad(Structure):
    _fields_ = [("fx", c_double), ("fy", c_double), ("normal", c_double),
                ("tangential", c_double), ("torque", c_double), ("length", c_double),
                ("x", c_double), ("y", c_double), ("offset", c_double), ("speed", c_double),
                ("contacts", c_int), ("servo_flips", c_long),
                ("servo_flip_time", c_double)]


class SimSink(Structure):
    _fields_ = [("shape", c_int), ("level", c_double), ("x0", c_double), ("y0", c_double),
                ("x1", c_double), ("y1", c_double)]


class SimBodyForceView(Structure):
    _fields_ = [("count", c_int), ("time", c_double), ("x", _pd), ("y", _pd), ("vx", _pd),
                ("vy", _pd), ("radius", _pd), ("mass", _pd), ("fx", _pd), ("fy", _pd)]


BODY_FORCE_FN = CFUNCTYPE(None, c_void_p, POINTER(SimBodyForceView))


class SimBodyForce(Structure):
    _fields_ = [("apply", BODY_FORCE_FN), ("context", c_void_p)]


class SimWallBody(Structure):
    _fields_ = [("active", c_int), ("axis_x", c_double), ("axis_y", c_double),
                ("mass", c_double), ("force_x", c_double), ("force_y", c_double),
                ("gravity", c_int), ("servo", c_int), ("target", c_double), ("gain", c_double),
                ("max_speed", c_double), ("length_kind", c_int), ("length", c_double),
                ("between", c_int * 2), ("rotation", c_int), ("inertia", c_double),
                ("servo_explicit", c_int)]


class SimWorldDef(Structure):
    _fields_ = [("effects", c_uint), ("contact", SimContactModel), ("mass_model", c_int),
                ("species_count", c_int), ("materials", SimMaterial * SIM_MAX_SPECIES),
                ("gravity_x", c_double), ("gravity_y", c_double), ("integrator", c_int),
                ("time_step", c_double), ("steps_per_contact", c_double),
                ("max_dt_fraction", c_double), ("skin", c_double), ("domain_x0", c_double),
                ("domain_x1", c_double), ("grains", SimGrainSet), ("wall_count", c_int),
                ("walls", POINTER(SimWall)), ("wall_bodies", POINTER(SimWallBody)),
                ("grain_bodies", POINTER(SimWallBody)), ("grain_body_count", c_int),
                ("motion_count", c_int),
                ("motions", SimMotion * SIM_MAX_MOTIONS), ("sink_count", c_int),
                ("sinks", SimSink * SIM_MAX_SINKS), ("body_force", SimBodyForce),
                ("guard_max_overlap", c_double), ("guard_max_speed", c_double),
                ("guard_every", c_int), ("max_initial_overlap", c_double),
                ("length_scale", c_double), ("start_time", c_double)]


class SimError(Structure):
    _fields_ = [("status", c_int), ("field", c_char * 64), ("message", c_char * 400),
                ("step", c_long), ("grain", c_long)]


class SimTiming(Structure):
    _fields_ = [("contact_time_min", c_double), ("stability_limit", c_double),
                ("time_step", c_double), ("steps_per_contact", c_double),
                ("restitution", c_double)]


class SimContact(Structure):
    _fields_ = [("i", c_int), ("j", c_int), ("normal_force", c_double),
                ("tangential_force", c_double), ("overlap", c_double), ("x", c_double),
                ("y", c_double), ("nx", c_double), ("ny", c_double)]


class SimFrame(Structure):
    _fields_ = [("count", c_int), ("mobile_count", c_int), ("step", c_long), ("time", c_double),
                ("time_scale", c_double), ("x", _pd), ("y", _pd), ("angle", _pd),
                ("radius", _pd), ("vx", _pd), ("vy", _pd), ("omega", _pd), ("species", _pi),
                ("flags", _pu), ("id", _pu32), ("force", _pd), ("fx", _pd), ("fy", _pd),
                ("torque", _pd), ("contact_count", c_int), ("contacts", POINTER(SimContact)),
                ("wall_count", c_int), ("walls", POINTER(SimWall)), ("periodic", c_int),
                ("domain_x0", c_double), ("domain_x1", c_double)]


SIM_CG_FIELD_COUNT = 23


class SimCoarseDef(Structure):
    _fields_ = [("kernel", c_int), ("width", c_double), ("geometry", c_int), ("x0", c_double),
                ("y0", c_double), ("cell_x", c_double), ("cell_y", c_double), ("nx", c_int),
                ("ny", c_int), ("x1", c_double), ("y1", c_double), ("contacts", c_int),
                ("normalise", c_int)]


class SimEnergy(Structure):
    _fields_ = [("kinetic", c_double), ("potential", c_double), ("rotational", c_double),
                ("elastic", c_double), ("total", c_double), ("mobile", c_int),
                ("contacts", c_int)]


class SimRng(Structure):
    _fields_ = [("s", c_uint64 * 4)]


class SimGrainBuffer(Structure):
    _fields_ = [("count", c_int), ("capacity", c_int), ("x", _pd), ("y", _pd), ("radius", _pd),
                ("vx", _pd), ("vy", _pd), ("angle", _pd), ("omega", _pd), ("species", _pi),
                ("motion", _pi), ("flags", _pu), ("id", _pu32)]


class SimRainDef(Structure):
    _fields_ = [("x0", c_double), ("x1", c_double), ("y0", c_double), ("y1", c_double),
                ("radius_mean", c_double), ("polydispersity", c_double),
                ("pitch_radius", c_double), ("column_gap", c_double), ("row_gap", c_double),
                ("column_jitter", c_double), ("row_jitter", c_double), ("max_count", c_int),
                ("species", c_int), ("species_fraction", c_double * SIM_MAX_SPECIES),
                ("species_radius", c_double * SIM_MAX_SPECIES)]


# ------------------------------------------------------------------ render/render.h


class RenderStyle(Structure):
    _fields_ = [("width", c_int), ("height", c_int), ("view_x0", c_double),
                ("view_y0", c_double), ("view_x1", c_double), ("view_y1", c_double),
                ("color_by", c_int), ("colormap", c_int), ("range_min", c_double),
                ("range_max", c_double), ("band_height", c_double), ("fill_rgb", c_uint32),
                ("fixed_rgb", c_uint32), ("background_rgb", c_uint32), ("outline", c_int),
                ("orientation_tick", c_int), ("force_chains", c_int),
                ("chain_threshold", c_double), ("chain_width_max", c_double),
                ("velocity_arrows", c_int), ("velocity_field", c_int),
                ("field_cell", c_double), ("field_width", c_double), ("field_kernel", c_int),
                ("arrow_scale", c_double), ("colorbar", c_int), ("colorbar_label", c_char_p),
                ("colorbar_unit", c_char_p), ("time_stamp", c_int), ("scale_bar", c_int),
                ("title", c_char_p), ("arch_ids", _pi), ("arch_inset", c_int),
                ("band_rgb", c_uint32), ("initial_y", _pd), ("initial_y_count", c_int),
                ("chain_force_max", c_double), ("arch_rgb", c_uint32), ("font_size", c_double),
                ("reduced_units", c_int), ("axes", c_int),
                ("species_names", POINTER(c_char_p)), ("species_name_count", c_int),
                ("dpi", c_double), ("field_color", c_int), ("node_vx", _pd), ("node_vy", _pd),
                ("node_nx", c_int), ("node_ny", c_int), ("node_x0", c_double),
                ("node_y0", c_double), ("node_cell", c_double),
                ("normalised_units", c_int), ("color_extend", c_int), ("arrow_min", c_double),
                ("force_unit", c_double), ("speed_unit", c_double)]


class RenderMeta(Structure):
    _fields_ = [("scene", c_char_p), ("seed", c_uint64), ("comment", c_char_p)]


# ------------------------------------------------------------------ app/scene/scene.h (a prefix)

SCENE_MAX_STAGES = 8
SCENE_NAME_MAX = 64
SCENE_PATH_MAX = 1024


class SceneDrag(Structure):
    _fields_ = [("model", c_int), ("coefficient", c_double), ("viscosity", c_double),
                ("fluid_vx", c_double), ("fluid_vy", c_double)]


class SceneStage(Structure):
    _fields_ = [("name", c_char * SCENE_NAME_MAX), ("load", c_int),
                ("load_path", c_char * SCENE_PATH_MAX), ("time_step", c_double),
                ("duration", c_double), ("settle_kinetic", c_double),
                ("settle_after", c_double), ("settle_per_grain", c_double),
                ("settle_hold", c_double), ("remove_count", c_int), ("remove_ids", _pu32),
                ("movie", c_int), ("skip", c_int), ("gravity_x", c_double),
                ("gravity_y", c_double), ("effects", c_uint), ("motions", c_uint),
                ("restart_motions", c_uint), ("declares_motions", c_int),
                ("movie_view", c_double * 4), ("add_count", c_int), ("adds", c_void_p)]


class Scene(Structure):
    """The leading fields of app/scene/scene.h's Scene, read only (the loader allocates it)."""
    _fields_ = [("path", c_char * SCENE_PATH_MAX), ("name", c_char * SCENE_NAME_MAX),
                ("seed", c_uint64), ("def", SimWorldDef), ("grains", SimGrainBuffer),
                ("fixed_count", c_int), ("walls", POINTER(SimWall)),
                ("wall_bodies", POINTER(SimWallBody)),
                ("motion_names", (c_char * SCENE_NAME_MAX) * SIM_MAX_MOTIONS),
                ("species_names", (c_char * SCENE_NAME_MAX) * SIM_MAX_SPECIES),
                ("drag", SceneDrag), ("stage_count", c_int),
                ("stages", SceneStage * SCENE_MAX_STAGES)]


# name -> (header to include, struct type) for the layout probe of the tests
STRUCTS = {
    "SimMaterial": ("sim/sim.h", SimMaterial), "SimContactModel": ("sim/sim.h", SimContactModel),
    "SimGrainSet": ("sim/sim.h", SimGrainSet), "SimMotion": ("sim/sim.h", SimMotion),
    "SimWall": ("sim/sim.h", SimWall), "SimSink": ("sim/sim.h", SimSink),
    "SimWallBody": ("sim/sim.h", SimWallBody), "SimWallLoad": ("sim/sim.h", SimWallLoad),
    "SimBodyForceView": ("sim/sim.h", SimBodyForceView),
    "SimBodyForce": ("sim/sim.h", SimBodyForce), "SimWorldDef": ("sim/sim.h", SimWorldDef),
    "SimError": ("sim/sim.h", SimError), "SimTiming": ("sim/sim.h", SimTiming),
    "SimContact": ("sim/sim.h", SimContact), "SimFrame": ("sim/sim.h", SimFrame),
    "SimEnergy": ("sim/sim.h", SimEnergy), "SimRng": ("sim/sim.h", SimRng),
    "SimGrainBuffer": ("sim/sim.h", SimGrainBuffer), "SimRainDef": ("sim/sim.h", SimRainDef),
    "SimCoarseDef": ("sim/sim.h", SimCoarseDef),
    "RenderStyle": ("render/render.h", RenderStyle), "RenderMeta": ("render/render.h", RenderMeta),
    "SceneDrag": ("scene/scene.h", SceneDrag), "SceneStage": ("scene/scene.h", SceneStage),
    "Scene": ("scene/scene.h", Scene),
}

# ------------------------------------------------------------------ functions

_P_WORLD = c_void_p
_P_ERR = POINTER(SimError)
# app/run/run.h AppRunHook: int (*)(void *context, SimWorld *world, int stage, long step)
RUN_HOOK = CFUNCTYPE(c_int, c_void_p, c_void_p, c_int, c_long)

_SIM_FUNCTIONS = {
    "sim_effect_from_name": (c_uint, [c_char_p]),
    "sim_effect_name": (c_char_p, [c_uint]),
    "sim_integrator_from_name": (c_int, [c_char_p]),
    "sim_integrator_name": (c_char_p, [c_int]),
    "sim_world_def_default": (SimWorldDef, []),
    "sim_material_default": (SimMaterial, []),
    "sim_world_def_validate": (c_int, [POINTER(SimWorldDef), _P_ERR]),
    "sim_world_def_timing": (SimTiming, [POINTER(SimWorldDef)]),
    "sim_world_create": (_P_WORLD, [POINTER(SimWorldDef), _P_ERR]),
    "sim_world_destroy": (None, [_P_WORLD]),
    "sim_world_step": (c_int, [_P_WORLD, c_long, _P_ERR]),
    "sim_world_time": (c_double, [_P_WORLD]),
    "sim_world_step_count": (c_long, [_P_WORLD]),
    "sim_world_time_step": (c_double, [_P_WORLD]),
    "sim_world_effects": (c_uint, [_P_WORLD]),
    "sim_world_timing": (SimTiming, [_P_WORLD]),
    "sim_world_grain_count": (c_int, [_P_WORLD]),
    "sim_world_mobile_count": (c_int, [_P_WORLD]),
    "sim_isa": (c_int, []),
    "sim_isa_name": (c_char_p, [c_int]),
    "sim_isa_from_name": (c_int, [c_char_p]),
    "sim_isa_supported": (c_int, [c_int]),
    "sim_isa_set": (c_int, [c_int]),
    "sim_world_skin": (c_double, [_P_WORLD]),
    "sim_world_list_builds": (c_long, [_P_WORLD]),
    "sim_world_frame": (None, [_P_WORLD, POINTER(SimFrame)]),
    "sim_world_energy": (SimEnergy, [_P_WORLD]),
    "sim_world_coordination": (c_double, [_P_WORLD]),
    "sim_world_packing_fraction": (c_double, [_P_WORLD, c_double, c_double, c_double, c_double]),
    "sim_world_max_overlap_ratio": (c_double, [_P_WORLD]),
    "sim_world_means": (None, [_P_WORLD, _pd, _pd]),
    "sim_world_removed_count": (c_long, [_P_WORLD, c_int]),
    "sim_world_momentum": (None, [_P_WORLD, _pd, _pd]),
    "sim_world_hash": (c_uint64, [_P_WORLD]),
    "sim_world_surface_profile": (None, [_P_WORLD, c_double, c_double, c_int, _pd]),
    "sim_world_hexatic_order": (c_double, [_P_WORLD]),
    "sim_world_remove_rect": (c_int, [_P_WORLD, c_double, c_double, c_double, c_double]),
    "sim_world_remove_ids": (c_int, [_P_WORLD, _pu32, c_int]),
    "sim_world_add_grains": (c_int, [_P_WORLD, POINTER(SimGrainSet), _P_ERR]),
    "sim_world_freeze": (None, [_P_WORLD]),
    "sim_world_wall_load": (c_int, [_P_WORLD, c_int, POINTER(SimWallLoad)]),
    "sim_world_set_grains": (c_int, [_P_WORLD, POINTER(SimGrainSet), _P_ERR]),
    "sim_world_set_gravity": (None, [_P_WORLD, c_double, c_double]),
    "sim_world_set_motion": (None, [_P_WORLD, c_int, c_double, c_double]),
    "sim_world_masses": (None, [_P_WORLD, _pd]),
    "sim_coarse_def_default": (SimCoarseDef, []),
    "sim_coarse_create": (c_void_p, [POINTER(SimCoarseDef), _P_ERR]),
    "sim_coarse_destroy": (None, [c_void_p]),
    "sim_coarse_nodes": (c_int, [c_void_p]),
    "sim_coarse_node": (None, [c_void_p, c_int, _pd, _pd]),
    "sim_coarse_add": (c_int, [c_void_p, POINTER(SimFrame), _pd, c_double, c_double]),
    "sim_coarse_samples": (c_int, [c_void_p]),
    "sim_coarse_field": (None, [c_void_p, c_int, _pd]),
    "sim_coarse_field_from_name": (c_int, [c_char_p]),
    "sim_coarse_field_name": (c_char_p, [c_int]),
    "sim_coarse_field_unit": (c_char_p, [c_int]),
    "sim_coarse_field_needs_contacts": (c_int, [c_int]),
    "sim_world_save": (c_int, [_P_WORLD, c_char_p, _P_ERR]),
    "sim_world_restore_contacts": (c_int, [_P_WORLD, c_char_p, _P_ERR]),
    "sim_world_load": (_P_WORLD, [c_char_p, POINTER(SimWorldDef), _P_ERR]),
    "sim_rng_seed": (None, [POINTER(SimRng), c_uint64]),
    "sim_grain_buffer_init": (None, [POINTER(SimGrainBuffer)]),
    "sim_grain_buffer_free": (None, [POINTER(SimGrainBuffer)]),
    "sim_grain_buffer_add": (c_int, [POINTER(SimGrainBuffer), c_double, c_double, c_double,
                                     c_int, c_uint, c_int]),
    "sim_build_fixed_row": (None, [POINTER(SimGrainBuffer), c_double, c_double, c_double,
                                   c_double, c_int, c_int]),
    "sim_build_fixed_column": (None, [POINTER(SimGrainBuffer), c_double, c_double, c_double,
                                      c_double, c_int, c_int]),
    "sim_build_rain": (c_int, [POINTER(SimGrainBuffer), POINTER(SimRainDef), POINTER(SimRng)]),
    "sim_rain_def_thesis000": (SimRainDef, [c_double, c_double, c_double, c_double, c_int]),
    "sim_build_fixed_box": (None, [POINTER(SimGrainBuffer), c_double, c_double, c_double,
                                   c_double, c_double, c_int]),
}

_SIM_OPTIONAL = {
    "sim_world_set_threads": (None, [_P_WORLD, c_int]),
    "sim_world_threads": (c_int, [_P_WORLD]),
}

_RENDER_FUNCTIONS = {
    "render_style_default": (RenderStyle, []),
    "render_figure_write": (c_int, [POINTER(SimFrame), POINTER(RenderStyle), POINTER(RenderMeta),
                                    c_char_p, c_char_p, c_size_t]),
}

_SCENE_FUNCTIONS = {
    "scene_load": (POINTER(Scene), [c_char_p, POINTER(c_char_p), c_int, c_char_p, c_size_t]),
    "scene_free": (None, [POINTER(Scene)]),
    "scene_world_def": (SimWorldDef, [POINTER(Scene), c_int]),
    "scene_stage_index": (c_int, [POINTER(Scene), c_char_p]),
    "scene_keys": (POINTER(c_char_p), [c_char_p, c_int]),
    "scene_material_default": (SimMaterial, []),
    "scene_run": (c_int, [POINTER(Scene), c_char_p, c_int, c_int, RUN_HOOK, c_void_p, c_long]),
}


def _bind(lib, table):
    for name, (restype, argtypes) in table.items():
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = argtypes
    return lib


_cache = {}


def sim():
    """libsablier-sim, loaded and typed on first use."""
    if "sim" not in _cache:
        lib = _bind(_loader.load("sablier-sim"), _SIM_FUNCTIONS)
        for name, proto in _SIM_OPTIONAL.items():  # newer than some libraries in use
            if hasattr(lib, name):
                _bind(lib, {name: proto})
        _cache["sim"] = lib
    return _cache["sim"]


def render():
    """libsablier-render, or None when it is not built (sablier built without rendering)."""
    if "render" not in _cache:
        sim()  # the renderer needs the physics library's symbols
        try:
            lib = _loader.load("sablier-render")
        except OSError:
            lib = None
        _cache["render"] = _bind(lib, _RENDER_FUNCTIONS) if lib is not None else None
    return _cache["render"]


def scene():
    """libsablier-scene (the scene loader), or None when it is not built."""
    if "scene" not in _cache:
        sim()
        try:
            lib = _loader.load("sablier-scene")
        except OSError:
            lib = None
        _cache["scene"] = _bind(lib, _SCENE_FUNCTIONS) if lib is not None else None
    return _cache["scene"]


def as_bytes(path):
    """A path or str as the bytes C expects."""
    return os.fsencode(path)


def error_text(err):
    return err.message.decode("utf-8", "replace"), err.field.decode("utf-8", "replace")

