#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Debian packages from a CMake build folder (docs/install.md, "Debian packages"):
#
#   scripts/deb.sh BUILD_DIR OUT_DIR
#
# Builds BUILD_DIR (configured beforehand; CI passes its Release build/), then runs debhelper
# over its install tree with the debian/ folder cmake/package.cmake wrote there: stripped
# programs and libraries with their -dbgsym packages, shlibs, symbols files and ldconfig
# triggers, gzipped manual page and changelogs. The .deb files land in OUT_DIR. Needs debhelper
# and dpkg-dev (scripts/setup.sh); no root (Rules-Requires-Root: no).
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: scripts/deb.sh BUILD_DIR OUT_DIR" >&2; exit 2; }
build=$(cd "$1" && pwd)
mkdir -p "$2"
out=$(cd "$2" && pwd)
[ -f "$build/debian/control" ] || { echo "deb.sh: $build has no debian/ (not a sablier build folder?)" >&2; exit 2; }
cmake --build "$build" -j "${JOBS:-$(nproc)}" >/dev/null
# dh works in <work>/src/debian and writes the packages to <work>
work=$(mktemp -d "${TMPDIR:-/tmp}/sablier-deb.XXXXXX")
# The libraries, pkg-config files and CMake package go to Debian's multiarch folder
# (/usr/lib/x86_64-linux-gnu): the build folder's CMAKE_INSTALL_LIBDIR is set so for the
# packages, then given back (it changes install rules only, nothing is compiled again).
libdir=$(sed -n 's/^CMAKE_INSTALL_LIBDIR:[A-Z]*=//p' "$build/CMakeCache.txt")
multiarch=lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH)
restore() {
  [ "$libdir" = "$multiarch" ] || cmake "$build" -DCMAKE_INSTALL_LIBDIR="$libdir" >/dev/null
  rm -rf "$work"
}
trap restore EXIT
[ "$libdir" = "$multiarch" ] || cmake "$build" -DCMAKE_INSTALL_LIBDIR="$multiarch" >/dev/null
mkdir -p "$work/src"
cp -r "$build/debian" "$work/src/debian"
chmod +x "$work/src/debian/rules"
(cd "$work/src" && SABLIER_BUILD=$build DEB_RULES_REQUIRES_ROOT=no debian/rules binary) \
  >"$work/dh.log" 2>&1 || { cat "$work/dh.log" >&2; echo "deb.sh: debhelper failed" >&2; exit 1; }
mv "$work"/*.deb "$out"/
ls "$out"/*.deb
