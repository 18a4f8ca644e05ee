#!/usr/bin/env bash
# Installs the Debian 12 packages sablier needs, only those missing. Run as root (or with sudo).
set -euo pipefail
# g++: the C++ client of tests/install/check.sh; dpkg-dev, debhelper and lintian: the Debian packages
#   (scripts/deb.sh) and their check;
# clang-14 and libclang-rt-14-dev: the libFuzzer harnesses of tests/fuzz;
# lammps and python3-vtk9: the real readers of the dump round trips (tests/clients/);
# libpoppler-glib-dev and librsvg2-dev: `sablier diff` compares PDF and SVG figures by their pixels;
# poppler-utils: pdftotext for the figure lint (tests/lint/figure_lint.py) and pdffonts.
# python3-venv, python3-setuptools and python3-wheel: the offline `pip install ./python` of
#   tests/python/venv_install.sh (docs/python.md).
# Not installed by default: python3-matplotlib for bench/plot_vs_matplotlib.sh, through
#   SABLIER_SETUP_EXTRA="python3-matplotlib" bash scripts/setup.sh
packages=(gcc g++ make cmake pkg-config dpkg-dev debhelper lintian file libconfig-dev libcairo2-dev libpng-dev
          libpoppler-glib-dev poppler-utils librsvg2-dev libosmesa6-dev libavcodec-dev libavformat-dev libswscale-dev libavutil-dev fonts-dejavu-core
          clang-format-14 python3-numpy clang-14 libclang-rt-14-dev lammps python3-vtk9
          openmpi-bin libopenmpi-dev python3-venv python3-setuptools python3-wheel)
if [ "${SABLIER_SETUP_EXTRA:-}" != "" ]; then
  read -r -a extra <<<"$SABLIER_SETUP_EXTRA"
  packages+=("${extra[@]}")
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q >/dev/null
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
