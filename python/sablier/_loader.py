# SPDX-License-Identifier: MIT
"""Finding sablier's shared libraries and its `sablier` command.

Search order for a library `libNAME.so` (NAME = sablier-sim, sablier-render, sablier-scene):

1. the folders of the environment variable SABLIER_LIB_DIR (os.pathsep-separated), each with
   its sub-folders sim/, render/, app/, lib/ and sablier/ (so a CMake build tree can be given
   as is, and an install's private folder <libdir>/sablier is searched);
2. an installed module (`cmake --install`, the .deb): the library folder that the install wrote
   into sablier/_installed.py, relative to the package (so a moved tree still finds its own);
3. the build tree of a source checkout, when this module is imported from <checkout>/python:
   <checkout>/build (same sub-folders);
4. the installed prefix: when the module lives in <prefix>/lib/python3*/.../sablier, the folders
   <prefix>/lib and <prefix>/lib/<multiarch>;
5. ctypes.util.find_library (ldconfig's cache, LD_LIBRARY_PATH).

libsablier-render and libsablier-scene are then looked for only where libsablier-sim was found.

The `sablier` command: SABLIER_EXECUTABLE, then `sablier` in the folders of 1 and their parents,
the installed command folder of 2, `sablier` in the folders of 3 and their parents, then
<prefix>/bin, then PATH.
"""
import ctypes
import ctypes.util
import glob
import os
import shutil
import sysconfig

# sablier/: the private library folder of an install (<libdir>/sablier/libsablier-scene.so.0.N)
_SUBDIRS = ("", "sim", "render", "app", "lib", "sablier")
_HERE = os.path.dirname(os.path.abspath(__file__))


def _env_dirs():
    value = os.environ.get("SABLIER_LIB_DIR", "")
    return [d for d in value.split(os.pathsep) if d]


def _installed():
    """(library folder, command folder) recorded by cmake --install, or None in a checkout."""
    try:
        from . import _installed as record
    except ImportError:
        return None
    return (os.path.normpath(os.path.join(_HERE, record.LIBDIR)),
            os.path.normpath(os.path.join(_HERE, record.BINDIR)))


def _installed_dirs():
    record = _installed()
    return [record[0]] if record else []


def _checkout_dirs():
    # python/sablier/_loader.py -> <checkout>
    root = os.path.dirname(os.path.dirname(_HERE))
    if os.path.isfile(os.path.join(root, "sim", "sim.h")):
        return [os.path.join(root, "build")]
    return []


def _prefix_dirs():
    # <prefix>/lib/python3.11/site-packages/sablier or <prefix>/lib/python3/dist-packages/sablier
    parts = _HERE.split(os.sep)
    dirs = []
    for k in range(len(parts) - 1, 0, -1):
        if parts[k].startswith("python3") and k >= 2 and parts[k - 1] in ("lib", "lib64"):
            prefix = os.sep.join(parts[:k - 1]) or os.sep
            libdir = os.sep.join(parts[:k])
            dirs.append(libdir)
            multiarch = sysconfig.get_config_var("MULTIARCH")
            if multiarch:
                dirs.append(os.path.join(libdir, multiarch))
            dirs.append(os.path.join(prefix, "lib64"))
            break
    return dirs


def prefix_of_module():
    """<prefix> when the module is installed under <prefix>/lib/python3*/..., else None."""
    dirs = _prefix_dirs()
    return os.path.dirname(dirs[0]) if dirs else None


def _candidates(name, dirs):
    for base in dirs:
        for sub in _SUBDIRS:
            d = os.path.join(base, sub) if sub else base
            exact = os.path.join(d, "lib%s.so" % name)
            if os.path.isfile(exact):
                yield exact
            for versioned in sorted(glob.glob(os.path.join(d, "lib%s.so.*" % name))):
                yield versioned


def _tiers():
    yield _env_dirs()
    yield _installed_dirs()
    yield _checkout_dirs()
    yield _prefix_dirs()


_sim_tier = []


def find(name):
    """Path of libNAME.so by the search order above, or None. The render and scene libraries
    are looked for only where libsablier-sim was found (the same build tree or prefix), so one
    process never mixes libraries of two builds."""
    if name != "sablier-sim" and _sim_tier:
        tier = _sim_tier[0]
        if tier is None:
            return ctypes.util.find_library(name)
        for path in _candidates(name, tier):
            return path
        return None
    for dirs in _tiers():
        for path in _candidates(name, dirs):
            if name == "sablier-sim":
                _sim_tier[:] = [dirs]
            return path
    if name == "sablier-sim":
        _sim_tier[:] = [None]
    return ctypes.util.find_library(name)


_loaded = {}


def load(name):
    """ctypes.CDLL of libNAME (RTLD_GLOBAL, so the render and scene libraries bind to the very
    physics library loaded first); OSError when it cannot be found or loaded."""
    if name in _loaded:
        return _loaded[name]
    path = find(name)
    if path is None:
        raise OSError("sablier: lib%s.so not found (set SABLIER_LIB_DIR to the folder that holds "
                      "it, e.g. a build tree or <prefix>/lib)" % name)
    lib = ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)
    lib._sablier_path = path
    _loaded[name] = lib
    return lib


def path_of(name):
    """Path of the loaded library NAME (after load)."""
    return getattr(_loaded.get(name), "_sablier_path", None)


def executable():
    """Path of the `sablier` command, or None."""
    env = os.environ.get("SABLIER_EXECUTABLE")
    if env:
        return env

    def runnable(exe):
        return os.path.isfile(exe) and os.access(exe, os.X_OK)

    def search(bases):
        for base in bases:
            d = os.path.abspath(base)
            for _ in range(3):
                if runnable(os.path.join(d, "sablier")):
                    return os.path.join(d, "sablier")
                d = os.path.dirname(d)
        return None

    exe = search(_env_dirs())
    if exe:
        return exe
    record = _installed()
    if record and runnable(os.path.join(record[1], "sablier")):
        return os.path.join(record[1], "sablier")
    exe = search(_checkout_dirs())
    if exe:
        return exe
    prefix = prefix_of_module()
    if prefix:
        exe = os.path.join(prefix, "bin", "sablier")
        if os.path.isfile(exe) and os.access(exe, os.X_OK):
            return exe
    return shutil.which("sablier")
