# SPDX-License-Identifier: MIT
"""Figures of a world through libsablier-render, or the `sablier render` command without it."""
import ctypes
import os
import subprocess
import tempfile

from . import _capi as C
from . import _loader

COLOR_BY = {"fixed": 0, "force": 1, "speed": 2, "species": 3, "height": 4}
COLORMAP = {"viridis": 0, "yellow_red": 1, "greys": 2}


def available():
    """True when libsablier-render can be loaded (in-process figures)."""
    return C.render() is not None


def style(**fields):
    """A RenderStyle: render_style_default() with fields set by name (color_by and colormap may
    be names, view=(x0, y0, x1, y1), strings for title/colorbar_label/colorbar_unit)."""
    lib = C.render()
    s = lib.render_style_default()
    keep = []
    names = {f[0] for f in C.RenderStyle._fields_}
    for key, value in fields.items():
        if value is None:
            continue
        if key == "color_by" and isinstance(value, str):
            value = COLOR_BY[value]
        elif key == "colormap" and isinstance(value, str):
            value = COLORMAP[value]
        elif key == "view":
            s.view_x0, s.view_y0, s.view_x1, s.view_y1 = (float(v) for v in value)
            continue
        elif key not in names:
            raise ValueError("render style: unknown field %r" % key)
        if key in ("title", "colorbar_label", "colorbar_unit"):
            value = value.encode()
            keep.append(value)
        elif isinstance(value, bool):
            value = int(value)
        setattr(s, key, value)
    s._keep = keep
    return s


_CLI_FLAGS = {"force_chains": "--force-chains", "velocity_field": "--velocity-field",
              "velocity_arrows": "--velocity-arrows", "colorbar": "--colorbar",
              "time_stamp": "--time-stamp", "scale_bar": "--scale-bar"}
_CLI_VALUES = {"color_by": "--color-by", "colormap": "--colormap", "width": "--width",
               "height": "--height", "title": "--title", "chain_threshold": "--chain-threshold"}


def figure(world, path, scene_name="python", seed=0, scene=None, **fields):
    """Write a figure of `world` to path (.png, .pdf, .svg); returns path."""
    path = os.fspath(path)
    if available() and scene is None:
        s = style(**fields)
        frame = world.frame()
        meta = C.RenderMeta(scene_name.encode(), seed, b"sablier python module")
        err = ctypes.create_string_buffer(512)
        rc = C.render().render_figure_write(ctypes.byref(frame.raw), ctypes.byref(s),
                                            ctypes.byref(meta), C.as_bytes(path), err, len(err))
        if rc != 0:
            raise RuntimeError("render_figure_write %s: %s" % (path, err.value.decode()))
        return path
    exe = _loader.executable()
    if exe is None:
        raise OSError("sablier: neither libsablier-render nor the `sablier` command found")
    with tempfile.TemporaryDirectory(prefix="sablier-render-") as tmp:
        state = os.path.join(tmp, "frame.state")
        world.save(state)
        cmd = [exe, "render", state, "-o", path]
        if scene is not None:
            cmd += ["--scene", os.fspath(scene)]
        for key, value in fields.items():
            if key in _CLI_FLAGS:
                if value:
                    cmd.append(_CLI_FLAGS[key])
            elif key in _CLI_VALUES:
                cmd += [_CLI_VALUES[key], str(value)]
            else:
                raise ValueError("sablier render has no option for %r" % key)
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError("%s: exit %d: %s" % (" ".join(cmd), r.returncode, r.stderr))
    return path
