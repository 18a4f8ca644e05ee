#!/bin/sh
# SPDX-License-Identifier: MIT
# The Python module installed as users install it (docs/python.md, "Installing"):
#   python3 -m venv --system-site-packages v && v/bin/pip install --no-build-isolation --no-index ./python
# offline, with Debian's setuptools, from a copy of python/ (pip builds in the source folder);
# then tests/python/venv_demo.py runs with the environment's interpreter outside the source tree
# against the build's libraries (SABLIER_LIB_DIR). Last, `cmake --install` into a scratch
# prefix and the module imported from there as docs/install.md says (PYTHONPATH).
# Usage: venv_install.sh SOURCE_DIR BUILD_DIR
set -eu
src=$1
build=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src/python" "$tmp/src"
rm -rf "$tmp/src/build" "$tmp/src"/*.egg-info
/usr/bin/python3 -m venv --system-site-packages "$tmp/v"
"$tmp/v/bin/pip" install --no-build-isolation --no-index --quiet "$tmp/src"
mkdir "$tmp/out"
cd "$tmp"
SABLIER_LIB_DIR=$build PYTHONDONTWRITEBYTECODE=1 "$tmp/v/bin/python" "$src/tests/python/venv_demo.py" "$tmp/out"
"$tmp/v/bin/pip" uninstall --yes --quiet sablier
# the prefix's module on sys.path as documented
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
PYTHONPATH=$tmp/prefix/lib/python3/dist-packages /usr/bin/python3 -c '
import sys, sablier
lib = sablier.library_path()
print("installed module", sablier.__file__, "loads", lib)
assert sablier.__file__.startswith(sys.argv[1]) and lib.startswith(sys.argv[1]), lib
' "$tmp/prefix"
echo "venv install: ok"
