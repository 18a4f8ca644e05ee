#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# CI stage "install, out-of-tree clients, package" (docs/install.md).
#
#   tests/install/check.sh [BUILD_DIR] [--no-package]
#
# Builds BUILD_DIR (default: a fresh Release build in a temporary folder; .ci/run passes the
# build/ that `make test` then reuses), installs it into a temporary prefix and checks the tree;
# builds the programs of examples/installed/ outside the tree against that prefix, once with
# pkg-config and once with CMake's find_package(sablier), and checks that the C and C++ programs,
# shared and static, print the same lines; checks the man page against every command's --help;
# checks that Debian's /usr/bin/python3 imports the installed Python module, which loads the
# installed libraries and steps a world to the C program's hash; then, unless --no-package, makes
# the Debian packages (scripts/deb.sh), lists them with their sizes, runs lintian on them (no
# error, no warning), checks their control files and contents, installs them with dpkg -i on this
# system, runs the installed `sablier` (--version, a shipped scene), a pkg-config client and the
# Python module, and removes them. A build configured with SABLIER_WITH_RENDER=OFF installs the
# sim library only, and that is what is checked.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
jobs=${JOBS:-$(nproc)}
build=""
package=1
for arg in "$@"; do
  case $arg in
    --no-package) package=0 ;;
    *) build=$arg ;;
  esac
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/sablier-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install check: $*" >&2; exit 1; }
step() { echo "-- $*"; }

if [ -z "$build" ]; then
  build=$tmp/build
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_COMPILE_WARNING_AS_ERROR=ON >/dev/null
fi
build=$(cd "$build" && pwd)
cmake --build "$build" -j "$jobs" >/dev/null
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
version=$(cache CMAKE_PROJECT_VERSION)
# the SONAME's version: 0.x carries the minor (cmake/abi.cmake)
sover=${version%.*}
[ "${version%%.*}" = 0 ] || sover=${version%%.*}
libdir=$(cache CMAKE_INSTALL_LIBDIR)
render=$(cache SABLIER_WITH_RENDER)
case $render in ON | on | TRUE | true | 1) render=1 ;; *) render=0 ;; esac
libs=(sim)
[ $render = 1 ] && libs+=(render)

# ---- install tree
prefix=$tmp/prefix
step "cmake --install $build --prefix <tmp>/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
expect=(bin/sablier include/sablier/sim/sim.h share/man/man1/sablier.1
        share/doc/sablier/README.md share/doc/sablier/install.md share/doc/sablier/cli.md
        share/sablier/scenes/crater/quick.scene
        "$libdir/cmake/sablier/sablierConfig.cmake" "$libdir/cmake/sablier/sablierConfigVersion.cmake"
        "$libdir/cmake/sablier/sablierTargets.cmake")
for lib in "${libs[@]}"; do
  expect+=("$libdir/libsablier-$lib.a" "$libdir/libsablier-$lib.so" "$libdir/libsablier-$lib.so.$sover"
           "$libdir/libsablier-$lib.so.$version" "$libdir/pkgconfig/sablier-$lib.pc")
done
[ $render = 1 ] && expect+=(include/sablier/render/render.h include/sablier/render/render_image.h
                            include/sablier/render/render_style.h)
for f in "${expect[@]}"; do
  [ -e "$prefix/$f" ] || fail "missing $f in the install tree"
done
if [ $render = 0 ]; then
  [ ! -e "$prefix/$libdir/pkgconfig/sablier-render.pc" ] || fail "sim-only build installed sablier-render.pc"
  [ ! -e "$prefix/include/sablier/render" ] || fail "sim-only build installed render headers"
fi
for lib in "${libs[@]}"; do
  soname=$(readelf -d "$prefix/$libdir/libsablier-$lib.so.$version" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
  [ "$soname" = "libsablier-$lib.so.$sover" ] || fail "libsablier-$lib soname is '$soname'"
  # the version script (cmake/abi.cmake): nothing but sim_ or render_ functions exported
  others=$(nm -D --defined-only "$prefix/$libdir/libsablier-$lib.so.$version" | awk '{print $3}' |
           grep -v "^${lib}_" || true)
  [ -z "$others" ] || fail "libsablier-$lib exports $(echo $others)"
done
# the scene loader is private: <libdir>/sablier, no link for the linker, no headers
[ -e "$prefix/$libdir/sablier/libsablier-scene.so.$sover" ] || fail "no private $libdir/sablier/libsablier-scene.so.$sover"
if [ -e "$prefix/$libdir/sablier/libsablier-scene.so" ] || compgen -G "$prefix/$libdir/libsablier-scene*" >/dev/null; then
  fail "libsablier-scene is installed as a public library"
fi
echo "   $(cd "$prefix" && find . -type f -o -type l | grep -vc 'share/doc\|share/sablier') files" \
     "besides docs and scenes; sonames libsablier-{$(IFS=,; echo "${libs[*]}")}.so.$sover"

# ---- versions agree: the command, the library header, pkg-config and the man page
export PKG_CONFIG_PATH=$prefix/$libdir/pkgconfig
export LD_LIBRARY_PATH=$prefix/$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
[ "$("$prefix/bin/sablier" --version | head -1)" = "sablier $version" ] || fail "sablier --version is not $version"
[ "$(pkg-config --modversion sablier-sim)" = "$version" ] || fail "sablier-sim.pc version"
grep -q "^#define SIM_VERSION \"$version\"" "$prefix/include/sablier/sim/sim.h" || fail "SIM_VERSION is not $version"
grep -q "^\.TH SABLIER 1 .*\"sablier $version\"" "$prefix/share/man/man1/sablier.1" || fail "sablier.1 is not for $version"

# ---- the man page names every option of every command's --help
step "sablier(1) against sablier --help and each COMMAND --help"
man=$prefix/share/man/man1/sablier.1
commands=$("$prefix/bin/sablier" --help | sed -n '/^commands:/,/^$/{s/^  \([a-z][a-z]*\) .*/\1/p}')
[ -n "$commands" ] || fail "no commands in sablier --help"
for cmd in $commands; do
  grep -q "^\.BI \"$cmd \|^\.BI $cmd \|^\.B $cmd\$" "$man" || fail "sablier.1 has no entry for '$cmd'"
  for opt in $("$prefix/bin/sablier" "$cmd" --help | grep -o -- '--[a-z][a-z0-9-]*' | sort -u); do
    grep -qF -- "${opt//-/\\-}" "$man" || fail "sablier.1 does not mention $cmd's option $opt"
  done
done
echo "   $(echo $commands | wc -w) commands, every option documented"

# ---- out-of-tree clients: pkg-config
src=$root/examples/installed
out=$tmp/clients
mkdir -p "$out"
cflags=(-Wall -Wextra -Wpedantic -Werror)
step "out of tree with pkg-config: C17, C++17, static"
cc -std=c17 "${cflags[@]}" "$src/hello_sim.c" $(pkg-config --cflags --libs sablier-sim) -o "$out/pc_c"
c++ -std=c++17 "${cflags[@]}" "$src/hello_sim.cpp" $(pkg-config --cflags --libs sablier-sim) -o "$out/pc_cpp"
# static: the archive by name, the rest from Libs.private
cc -std=c17 "${cflags[@]}" "$src/hello_sim.c" $(pkg-config --cflags sablier-sim) \
   $(pkg-config --static --libs sablier-sim | sed 's/-lsablier-sim/-l:libsablier-sim.a/') -o "$out/pc_c_static"
if [ $render = 1 ]; then
  cc -std=c17 "${cflags[@]}" "$src/hello_render.c" $(pkg-config --cflags --libs sablier-render) -o "$out/pc_render"
fi

# ---- out-of-tree clients: CMake package
step "out of tree with find_package(sablier): C17, C++17, static"
cmake -S "$src" -B "$tmp/cmake-clients" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_COMPILE_WARNING_AS_ERROR=ON >/dev/null
cmake --build "$tmp/cmake-clients" -j "$jobs" >/dev/null

# ---- they all print the same lines
"$out/pc_c" >"$out/pc_c.txt"
grep -q '^hash 0x[0-9a-f]\{16\}$' "$out/pc_c.txt" || fail "hello_sim printed no hash"
for p in "$out/pc_cpp" "$out/pc_c_static" "$tmp/cmake-clients/hello_sim" "$tmp/cmake-clients/hello_sim_cpp" \
         "$tmp/cmake-clients/hello_sim_static"; do
  "$p" >"$p.txt"
  cmp -s "$out/pc_c.txt" "$p.txt" || { diff "$out/pc_c.txt" "$p.txt" >&2; fail "${p#$tmp/} differs from the C program"; }
done
sed 's/^/   /' "$out/pc_c.txt"
echo "   the same from C and C++, shared and static, pkg-config and find_package (6 programs)"
if [ $render = 1 ]; then
  "$out/pc_render" "$out/a.png" >/dev/null
  "$tmp/cmake-clients/hello_render" "$out/b.png" >/dev/null
  "$tmp/cmake-clients/hello_render_static" "$out/c.png" >/dev/null
  cmp -s "$out/a.png" "$out/b.png" && cmp -s "$out/a.png" "$out/c.png" || fail "hello_render figures differ"
  echo "   hello_render: the same 640x480 figure from pkg-config, find_package and the static library"
fi

# ---- the Python module from the install tree, with Debian's interpreter (docs/python.md)
# python_check PYDIR PREFIX: `import sablier` from PYDIR loads the libraries under PREFIX by itself
# (no SABLIER_LIB_DIR, no LD_LIBRARY_PATH) and steps hello_sim.c's world to the C program's hash.
python_check() {
  local got
  got=$(cd "$tmp" && env -u SABLIER_LIB_DIR -u SABLIER_EXECUTABLE -u LD_LIBRARY_PATH PYTHONPATH="$1" \
        PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c "
import sablier, os
for name in ('sablier-sim', 'sablier-scene'):
    path = os.path.realpath(sablier.library_path(name))
    assert path.startswith(os.path.realpath('$2') + os.sep), '%s from %s' % (name, path)
exec(open('$src/hello_sim.py').read())") || fail "python3 -c 'import sablier' from $1 failed"
  grep -qx "$(grep '^hash ' "$out/pc_c.txt")" <<<"$got" ||
    fail "the Python module from $1 does not give the C hash: $got"
  echo "   $(grep '^hash ' <<<"$got"): the same as the C program, from $1 (libraries under $2)"
}
python=0
if [ -x /usr/bin/python3 ] && /usr/bin/python3 -c "import numpy" 2>/dev/null &&
   [ -e "$prefix/$libdir/sablier/libsablier-scene.so.$sover" ]; then
  python=1
fi
pyrel=$(cache SABLIER_PYTHON_DIR)
case $pyrel in /*) pydir=$pyrel ;; *) pydir=$prefix/$pyrel ;; esac
if [ $python = 1 ]; then
  step "/usr/bin/python3 -c 'import sablier' against the install tree"
  [ -f "$pydir/sablier/__init__.py" ] && [ -f "$pydir/sablier/_installed.py" ] ||
    fail "the Python package is not installed in $pydir"
  python_check "$pydir" "$prefix"
fi

[ $package = 1 ] || exit 0


# ---- Debian packages (scripts/deb.sh, cmake/package.cmake)
step "scripts/deb.sh: the Debian packages"
bash "$root/scripts/deb.sh" "$build" "$tmp/deb" >"$tmp/deb.log" 2>&1 ||
  { cat "$tmp/deb.log" >&2; fail "scripts/deb.sh failed"; }
mpi=0
grep -q '^Package: sablier-mpi$' "$build/debian/control" && mpi=1
packages=("libsablier-sim$sover" libsablier-dev sablier python3-sablier)
[ $render = 1 ] && packages+=("libsablier-render$sover")
[ $mpi = 1 ] && packages+=(sablier-mpi)
deb_of() { echo "$tmp/deb/${1}_${version}_$(dpkg --print-architecture).deb"; }
for p in "${packages[@]}"; do
  [ -f "$(deb_of "$p")" ] || fail "no package $p"
  [ "$p" = libsablier-dev ] || [ -f "$(deb_of "$p-dbgsym")" ] || fail "no package $p-dbgsym"
done
echo "   package                        file size  installed size"
for d in "$tmp"/deb/*.deb; do
  printf '   %-30s %6d kB  %6d kB\n' "$(dpkg-deb -f "$d" Package)" $(( $(stat -c %s "$d") / 1024 )) \
    "$(dpkg-deb -f "$d" Installed-Size)"
done
step "lintian (no error, no warning)"
lintian --fail-on error,warning "$tmp"/deb/*.deb >"$tmp/lintian.log" 2>&1 ||
  { grep -v 'running with root privileges' "$tmp/lintian.log" >&2; fail "lintian found errors or warnings"; }
{ grep -v 'running with root privileges' "$tmp/lintian.log" || true; } | sed 's/^/   /'
echo "   lintian: no error, no warning in $(ls "$tmp"/deb/*.deb | wc -l) packages"

# control files: shlibs, symbols and the ldconfig trigger of each runtime library package; no
# MPI but in sablier-mpi; the development package depends on what sablier-render.pc requires
for p in "libsablier-sim$sover" $([ $render = 1 ] && echo "libsablier-render$sover"); do
  ctrl=$(dpkg-deb -I "$(deb_of "$p")")
  for f in shlibs symbols triggers; do
    grep -q " $f\$\| $f " <<<"$ctrl" || fail "$p has no $f control file"
  done
  dpkg-deb --ctrl-tarfile "$(deb_of "$p")" | tar -xO ./triggers | grep -qx 'activate-noawait ldconfig' ||
    fail "$p's trigger is not ldconfig's"
done
for p in "${packages[@]}"; do
  [ "$p" = sablier-mpi ] && continue
  ! dpkg-deb -f "$(deb_of "$p")" Depends | grep -qi mpi || fail "$p depends on MPI: $(dpkg-deb -f "$(deb_of "$p")" Depends)"
done
devdeps=$(dpkg-deb -f "$(deb_of libsablier-dev)" Depends)
need=("libsablier-sim$sover (= $version)")
[ $render = 1 ] && need+=("libsablier-render$sover (= $version)" libcairo2-dev libpng-dev libosmesa6-dev
                          libavcodec-dev libavformat-dev libavutil-dev libswscale-dev)
for d in "${need[@]}"; do
  grep -qF "$d" <<<"$devdeps" || fail "libsablier-dev does not depend on $d: $devdeps"
done
contents=$(dpkg-deb -c "$(deb_of sablier)" | awk '{print $6}')
for f in ./usr/bin/sablier ./usr/share/man/man1/sablier.1.gz ./usr/share/doc/sablier/copyright \
         ./usr/share/doc/sablier/changelog.gz ./usr/share/sablier/scenes/validation/drop_elastic.scene; do
  grep -qx -- "$f" <<<"$contents" || fail "the sablier package lacks $f"
done

# ---- install them on this system, use them, remove them
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
debs=()
for p in "${packages[@]}"; do debs+=("$(deb_of "$p")"); done
step "dpkg -i ${packages[*]}"
removed=0
remove() {
  [ $removed = 1 ] && return
  removed=1
  $SUDO dpkg -P "${packages[@]}" >"$tmp/dpkg-P.log" 2>&1 || { cat "$tmp/dpkg-P.log" >&2; return 1; }
}
trap 'remove; rm -rf "$tmp"' EXIT
$SUDO dpkg -i "${debs[@]}" >"$tmp/dpkg-i.log" 2>&1 || { cat "$tmp/dpkg-i.log" >&2; fail "dpkg -i failed"; }
file -L /usr/bin/sablier | grep -q ', stripped' || fail "/usr/bin/sablier is not stripped"
/usr/bin/sablier --version >"$tmp/version.txt"
sed 's/^/   /' "$tmp/version.txt"
[ "$(head -1 "$tmp/version.txt")" = "sablier $version" ] || fail "the installed sablier --version is not $version"
# portable: the hot loops are chosen at run time, not compiled for this CPU (docs/dev/isa.md)
if [ "$(uname -m)" = x86_64 ]; then
  grep -q '^kernels: .*(this CPU: sse2' "$tmp/version.txt" || fail "the packaged sablier is not portable (-march=native?)"
fi
echo "   ldd /usr/bin/sablier: $(ldd /usr/bin/sablier | wc -l) libraries, MPI: $(ldd /usr/bin/sablier | grep -c libmpi || true)"
if [ $mpi = 1 ]; then
  ldd /usr/libexec/sablier/sablier-mpi >"$tmp/ldd-mpi.txt"
  grep -q libmpi "$tmp/ldd-mpi.txt" || fail "sablier-mpi links no MPI library"
fi
/usr/bin/sablier run /usr/share/sablier/scenes/validation/drop_elastic.scene --out "$tmp/run" --quiet \
  >"$tmp/run.log" 2>&1 || { cat "$tmp/run.log" >&2; fail "the installed sablier's run of drop_elastic.scene failed"; }
grep -q '"status": *"ok"' "$tmp/run/summary.json" || fail "the installed sablier's run of drop_elastic.scene failed"
if [ $render = 1 ]; then
  /usr/bin/sablier render "$tmp/run/run.state" -o "$tmp/run/run.png" --colorbar --time-stamp >"$tmp/render.log" 2>&1 ||
    { cat "$tmp/render.log" >&2; fail "the installed sablier could not render its run"; }
  [ -s "$tmp/run/run.png" ] || fail "the installed sablier wrote no run.png"
fi
# a pkg-config client of the system's files: no PKG_CONFIG_PATH, no LD_LIBRARY_PATH (the
# library is found through ldconfig's cache, which the package's trigger refreshed)
env -u PKG_CONFIG_PATH cc -std=c17 "${cflags[@]}" "$src/hello_sim.c" \
  $(env -u PKG_CONFIG_PATH pkg-config --cflags --libs sablier-sim) -o "$tmp/sys_hello_sim"
env -u LD_LIBRARY_PATH "$tmp/sys_hello_sim" >"$tmp/sys_hello_sim.txt"
cmp -s "$out/pc_c.txt" "$tmp/sys_hello_sim.txt" || fail "the pkg-config client of the installed packages differs"
echo "   hello_sim.c with pkg-config against /usr: $(grep '^hash ' "$tmp/sys_hello_sim.txt")"
if [ $python = 1 ]; then
  python_check /usr/lib/python3/dist-packages /usr
fi
remove || fail "dpkg -P failed"
[ ! -e /usr/bin/sablier ] || fail "/usr/bin/sablier is still there after dpkg -P"
echo "   installed, used and removed: ${packages[*]}"
