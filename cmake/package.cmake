# SPDX-License-Identifier: MIT
# `cpack -G DEB` in a build folder makes sablier_<version>_<arch>.deb: the install tree of
# cmake/install.cmake under /usr (docs/install.md). Runtime dependencies come from
# dpkg-shlibdeps on the binary and shared libraries when it is there (dpkg-dev), else from the
# Debian 12 list below.
set(CPACK_PACKAGE_NAME sablier)
set(CPACK_PACKAGE_VENDOR "sablier maintainers")
set(SABLIER_DEB_MAINTAINER "sablier maintainers <maintainers@users.noreply.h-seed-3ed8b660.example>"
    CACHE STRING "Maintainer field of the .deb")
set(CPACK_PACKAGE_CONTACT "${SABLIER_DEB_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "2D soft-disk DEM simulator with headless figure and movie rendering")
set(CPACK_PACKAGE_DESCRIPTION
    "sablier simulates 2D granular materials with the discrete element method (soft disks) and
turns the simulation, as it runs, into publication figures and movies without a display. The
package holds the sablier command, the shared and static libraries libsablier-sim and
libsablier-render with their headers, pkg-config files and CMake package, the shipped scenes
(/usr/share/sablier/scenes), the documentation and the sablier(1) manual page.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
# Install with DESTDIR and prefix /usr, whatever the build's CMAKE_INSTALL_PREFIX: the install
# step then sees /usr, which the pkg-config files record.
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_SET_DESTDIR ON)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CPACK_PACKAGE_CONTACT}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
find_program(SABLIER_DPKG_SHLIBDEPS dpkg-shlibdeps)
find_program(SABLIER_FILE_PROGRAM file) # CPack's shlibdeps step runs file(1)
if(SABLIER_DPKG_SHLIBDEPS AND SABLIER_FILE_PROGRAM)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
  set(sablier_deb_depends "")
else()
  set(sablier_deb_depends "libc6, libconfig9")
  get_target_property(sablier_sim_interface sim INTERFACE_LINK_LIBRARIES)
  if(sablier_sim_interface MATCHES "OpenMP|gomp")
    string(APPEND sablier_deb_depends ", libgomp1")
  endif()
  if(SABLIER_WITH_RENDER)
    string(APPEND sablier_deb_depends ", libcairo2, libpng16-16, libosmesa6, libavcodec59, "
           "libavformat59, libswscale6, libavutil57")
    if(SABLIER_RASTER_FOUND)
      string(APPEND sablier_deb_depends ", libpoppler-glib8, librsvg2-2")
    endif()
  endif()
endif()
# The figures' text is drawn in DejaVu Sans (fontconfig finds it; other fonts move pixels).
if(SABLIER_WITH_RENDER)
  if(sablier_deb_depends)
    string(APPEND sablier_deb_depends ", ")
  endif()
  string(APPEND sablier_deb_depends "fonts-dejavu-core")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${sablier_deb_depends}")
# The Python module (/usr/lib/python3/dist-packages/sablier, docs/python.md) needs NumPy.
if(TARGET scene_shared)
  set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-numpy")
endif()
# The .deb is for any x86-64: its hot loops pick SSE2, AVX2 or AVX-512 at run time (docs/dev/isa.md).
# A -march=native build (SABLIER_NATIVE=ON) would make one that runs on CPUs like this one only.
if(SABLIER_NATIVE_ACTIVE)
  message(WARNING "SABLIER_NATIVE=ON: a .deb made from this build runs only on CPUs like this one")
endif()
# Debian's per-package documents (Debian policy 12.5, 12.7): /usr/share/doc/sablier/copyright
# (machine-readable, MIT) and changelog.Debian.gz (gzip -9n: no name, no time stamp). They go into
# every install tree's doc folder (they are true of a plain install too).
configure_file(${CMAKE_CURRENT_LIST_DIR}/debian/changelog.in ${PROJECT_BINARY_DIR}/debian/changelog.Debian
               @ONLY)
find_program(SABLIER_GZIP gzip)
if(SABLIER_GZIP)
  add_custom_command(OUTPUT ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz
    COMMAND ${SABLIER_GZIP} -9nc ${PROJECT_BINARY_DIR}/debian/changelog.Debian >
            ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz
    DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog.Debian VERBATIM)
  add_custom_target(debian_changelog ALL DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz)
  install(FILES ${PROJECT_BINARY_DIR}/debian/changelog.Debian.gz DESTINATION ${CMAKE_INSTALL_DOCDIR})
endif()
install(FILES ${CMAKE_CURRENT_LIST_DIR}/debian/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
set(CPACK_STRIP_FILES OFF)
include(CPack)
