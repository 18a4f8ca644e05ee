# SPDX-License-Identifier: MIT
# Debian packages (docs/install.md, "Debian packages"), made by debhelper from this build folder:
#   scripts/deb.sh BUILD_DIR OUT_DIR
# This file writes BUILD_DIR/debian/: the control file (package names carry the SONAME version,
# cmake/abi.cmake), the changelog, the copyright, rules, the symbols files recorded for the ABI
# check (tests/install/abi/) and one .install list per package:
#   libsablier-simV   libsablier-sim.so.V (V = SABLIER_SOVERSION)
#   libsablier-renderV libsablier-render.so.V (with rendering)
#   libsablier-dev    headers, static libraries, .so links, pkg-config files, CMake package
#   sablier           the command, sablier(1), scenes, docs
#   sablier-mpi       the MPI program (with MPI), /usr/libexec/sablier/sablier-mpi
#   python3-sablier   the Python module and the private libsablier-scene (/usr/lib/sablier)
set(SABLIER_DEB_MAINTAINER "sablier maintainers <maintainers@users.noreply.h-seed-3ed8b660.example>"
    CACHE STRING "Maintainer field of the Debian packages")
set(deb ${PROJECT_BINARY_DIR}/debian)
set(sim_pkg libsablier-sim${SABLIER_SOVERSION})
set(render_pkg libsablier-render${SABLIER_SOVERSION})
set(libdir ${CMAKE_INSTALL_LIBDIR})

set(SABLIER_DEB_DEV_DEPENDS "${sim_pkg} (= \${binary:Version})")
set(SABLIER_DEB_RENDER_STANZA "")
set(SABLIER_DEB_FONTS "")
set(SABLIER_DEB_MPI_STANZA "")
if(SABLIER_WITH_RENDER)
  # The figures' text is drawn in DejaVu Sans (fontconfig finds it; other fonts move pixels).
  set(SABLIER_DEB_FONTS ", fonts-dejavu-core")
  set(SABLIER_DEB_RENDER_STANZA "
Package: ${render_pkg}
Section: libs
Architecture: any
Depends: \${shlibs:Depends}, \${misc:Depends}, fonts-dejavu-core
Description: 2D soft-disk DEM simulator - rendering library
 sablier simulates 2D granular materials with the discrete element method
 (soft disks).
 .
 This package holds the shared library libsablier-render: figures (Cairo),
 frames (OSMesa), PNG images and MP4 movies of simulation frames, without a
 display.
")
  # the -dev packages of the modules sablier-render.pc requires (render/CMakeLists.txt)
  set(dev_of_cairo libcairo2-dev)
  set(dev_of_libpng libpng-dev)
  set(dev_of_osmesa libosmesa6-dev)
  set(dev_of_libavcodec libavcodec-dev)
  set(dev_of_libavformat libavformat-dev)
  set(dev_of_libavutil libavutil-dev)
  set(dev_of_libswscale libswscale-dev)
  set(dev_of_poppler-glib libpoppler-glib-dev)
  set(dev_of_librsvg-2.0 librsvg2-dev)
  string(APPEND SABLIER_DEB_DEV_DEPENDS ", ${render_pkg} (= \${binary:Version})")
  string(REPLACE " " ";" modules "${SABLIER_RENDER_MODULES_TEXT}")
  foreach(module ${modules})
    if(NOT dev_of_${module})
      message(FATAL_ERROR "cmake/package.cmake: no Debian -dev package known for ${module}")
    endif()
    string(APPEND SABLIER_DEB_DEV_DEPENDS ", ${dev_of_${module}}")
  endforeach()
endif()
if(TARGET sablier-mpi)
  set(SABLIER_DEB_MPI_STANZA "
Package: sablier-mpi
Architecture: any
Depends: sablier (= \${binary:Version}), \${shlibs:Depends}, \${misc:Depends}
Recommends: openmpi-bin
Description: 2D soft-disk DEM simulator - ensembles over MPI ranks
 sablier simulates 2D granular materials with the discrete element method
 (soft disks).
 .
 This package holds the MPI build of the sablier program. Under an MPI
 launcher (mpirun -n 4 sablier sweep FILE, for one) the sablier command runs
 it in its place, so that the members of sweeps and studies run on the ranks
 of the job.
")
endif()

configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/control.in ${deb}/control @ONLY)
configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/changelog.in ${deb}/changelog @ONLY)
configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/copyright ${deb}/copyright COPYONLY)
configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/rules ${deb}/rules COPYONLY)
file(WRITE ${deb}/${sim_pkg}.install "usr/${libdir}/libsablier-sim.so.*\n")
file(WRITE ${deb}/libsablier-dev.install "usr/include\nusr/${libdir}/libsablier-*.so\n"
  "usr/${libdir}/libsablier-*.a\nusr/${libdir}/pkgconfig\nusr/${libdir}/cmake\n")
file(WRITE ${deb}/sablier.install "usr/bin/sablier\nusr/share/man/man1\nusr/share/sablier\n"
  "usr/share/doc/sablier\n")
file(WRITE ${deb}/python3-sablier.install "usr/${libdir}/sablier\nusr/${SABLIER_PYTHON_DIR}/sablier\n")
# the symbols recorded for the ABI check are the packages' symbols files (dpkg-gensymbols fails
# when one of them is no longer exported)
configure_file(${PROJECT_SOURCE_DIR}/tests/install/abi/libsablier-sim.symbols ${deb}/${sim_pkg}.symbols
               COPYONLY)
if(SABLIER_WITH_RENDER)
  file(WRITE ${deb}/${render_pkg}.install "usr/${libdir}/libsablier-render.so.*\n")
  configure_file(${PROJECT_SOURCE_DIR}/tests/install/abi/libsablier-render.symbols
                 ${deb}/${render_pkg}.symbols COPYONLY)
endif()
if(TARGET sablier-mpi)
  file(WRITE ${deb}/sablier-mpi.install "usr/${CMAKE_INSTALL_LIBEXECDIR}/sablier\n")
endif()
# The .deb is for any x86-64: its hot loops pick SSE2, AVX2 or AVX-512 at run time (docs/dev/isa.md).
# A -march=native build (SABLIER_NATIVE=ON) would make packages that run on CPUs like this one only.
if(SABLIER_NATIVE_ACTIVE)
  message(WARNING "SABLIER_NATIVE=ON: packages made from this build run only on CPUs like this one")
endif()
