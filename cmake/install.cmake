# SPDX-License-Identifier: MIT
# Install rules (docs/install.md): the `sablier` command, shared and static libsablier-sim and
# libsablier-render, their public headers under include/sablier/, pkg-config files, the CMake
# package `sablier` (imported targets sablier::sim, sablier::render: shared; sablier::sim_static,
# sablier::render_static), the scenes, the docs and the man page sablier(1).
include(CMakePackageConfigHelpers)

set(SABLIER_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sablier)
set(SABLIER_INCLUDE_DIR ${CMAKE_INSTALL_INCLUDEDIR}/sablier)

install(TARGETS sablier RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The MPI program (app/CMakeLists.txt) is no command of its own: `sablier` runs it under mpirun.
if(TARGET sablier-mpi)
  install(TARGETS sablier-mpi RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/sablier)
endif()

set(sablier_libraries sim sim_shared)
if(SABLIER_WITH_RENDER)
  list(APPEND sablier_libraries render render_shared)
endif()
install(TARGETS ${sablier_libraries} EXPORT sablierTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${SABLIER_INCLUDE_DIR})

# The public headers keep their in-tree paths: clients write #include <sim/sim.h> with
# -I<prefix>/include/sablier (no top-level sim/ or render/ folder in /usr/include).
install(FILES ${PROJECT_SOURCE_DIR}/sim/sim.h DESTINATION ${SABLIER_INCLUDE_DIR}/sim)
if(SABLIER_WITH_RENDER)
  install(FILES ${PROJECT_SOURCE_DIR}/render/render.h ${PROJECT_SOURCE_DIR}/render/render_image.h
                ${PROJECT_SOURCE_DIR}/render/render_style.h
          DESTINATION ${SABLIER_INCLUDE_DIR}/render)
endif()

# pkg-config files are written at install time, so that their prefix is the one installed into
# (`cmake --install build --prefix DIR`, or /usr inside the .deb), not the configure-time one.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(SABLIER_PC_LIBDIR "${CMAKE_INSTALL_LIBDIR}")
  set(sablier_pc_dest "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
else()
  set(SABLIER_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(sablier_pc_dest "\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/pkgconfig")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(SABLIER_PC_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}/sablier")
else()
  set(SABLIER_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}/sablier")
endif()
set(SABLIER_PC_PREFIX "@CMAKE_INSTALL_PREFIX@") # filled by the install step
# Static linking: libm, and the thread library sim/ links (sim/CMakeLists.txt), if any.
set(SABLIER_PC_SIM_LIBS_PRIVATE "-lm")
get_target_property(sablier_sim_interface sim INTERFACE_LINK_LIBRARIES)
if(sablier_sim_interface MATCHES "OpenMP|gomp")
  string(PREPEND SABLIER_PC_SIM_LIBS_PRIVATE "-lgomp ")
elseif(sablier_sim_interface MATCHES "Threads")
  string(PREPEND SABLIER_PC_SIM_LIBS_PRIVATE "-pthread ")
endif()
set(sablier_pc_files sablier-sim)
if(SABLIER_WITH_RENDER)
  list(APPEND sablier_pc_files sablier-render)
endif()
foreach(pc ${sablier_pc_files})
  configure_file(${CMAKE_CURRENT_LIST_DIR}/${pc}.pc.in ${PROJECT_BINARY_DIR}/pkgconfig/${pc}.pc.in
                 @ONLY)
  install(CODE "
    configure_file(\"${PROJECT_BINARY_DIR}/pkgconfig/${pc}.pc.in\"
                   \"${PROJECT_BINARY_DIR}/pkgconfig/install/${pc}.pc\" @ONLY)
    file(INSTALL DESTINATION \"${sablier_pc_dest}\" TYPE FILE
         FILES \"${PROJECT_BINARY_DIR}/pkgconfig/install/${pc}.pc\")")
endforeach()

# CMake package: find_package(sablier [COMPONENTS sim render]).
install(EXPORT sablierTargets NAMESPACE sablier:: DESTINATION ${SABLIER_CMAKE_DIR})
if(SABLIER_WITH_RENDER)
  set(SABLIER_CONFIG_WITH_RENDER 1)
else()
  set(SABLIER_CONFIG_WITH_RENDER 0)
endif()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/sablierConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cmake/sablierConfig.cmake INSTALL_DESTINATION ${SABLIER_CMAKE_DIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/sablierConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/sablierConfig.cmake
              ${PROJECT_BINARY_DIR}/cmake/sablierConfigVersion.cmake
        DESTINATION ${SABLIER_CMAKE_DIR})

# The Python module (python/sablier, docs/python.md) and the library it needs beyond sim and
# render: libsablier-scene (the scene loader), private: in <libdir>/sablier, without the
# libsablier-scene.so link, headers or pkg-config file (no program outside sablier links it). SABLIER_PYTHON_DIR, relative to the prefix or
# absolute, defaults to Debian's lib/python3/dist-packages (on /usr/bin/python3's path when the
# prefix is /usr). The install writes sablier/_installed.py with the library and command folders
# relative to the package, so the installed module loads the installed libraries (not a build
# tree), also from a copy of the tree moved elsewhere (dpkg-deb -x).
set(SABLIER_PYTHON_DIR lib/python3/dist-packages CACHE STRING
    "Where cmake --install puts the Python package sablier (relative paths: under the prefix)")
if(TARGET scene_shared)
  install(TARGETS scene_shared LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/sablier NAMELINK_SKIP)
  if(IS_ABSOLUTE "${SABLIER_PYTHON_DIR}")
    set(sablier_py_dest "${SABLIER_PYTHON_DIR}")
  else()
    set(sablier_py_dest "\${CMAKE_INSTALL_PREFIX}/${SABLIER_PYTHON_DIR}")
  endif()
  if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
    set(sablier_py_libdir "${CMAKE_INSTALL_LIBDIR}")
  else()
    set(sablier_py_libdir "\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}")
  endif()
  if(IS_ABSOLUTE "${CMAKE_INSTALL_BINDIR}")
    set(sablier_py_bindir "${CMAKE_INSTALL_BINDIR}")
  else()
    set(sablier_py_bindir "\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}")
  endif()
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/sablier DESTINATION ${SABLIER_PYTHON_DIR}
          FILES_MATCHING PATTERN "*.py" PATTERN "_installed.py" EXCLUDE PATTERN "__pycache__" EXCLUDE)
  install(CODE "
    file(RELATIVE_PATH sablier_rel_lib \"${sablier_py_dest}/sablier\" \"${sablier_py_libdir}\")
    file(RELATIVE_PATH sablier_rel_bin \"${sablier_py_dest}/sablier\" \"${sablier_py_bindir}\")
    file(WRITE \"${PROJECT_BINARY_DIR}/python/_installed.py\"
         \"# Written by cmake --install: the installed libraries and command, relative to this package.\\nLIBDIR = \\\"\${sablier_rel_lib}\\\"\\nBINDIR = \\\"\${sablier_rel_bin}\\\"\\n\")
    file(INSTALL DESTINATION \"${sablier_py_dest}/sablier\" TYPE FILE
         FILES \"${PROJECT_BINARY_DIR}/python/_installed.py\")")
endif()

# Scenes (share/sablier/scenes, includes keep their relative paths), docs and the man page.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/sablier/scenes)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        PATTERN sablier.1 EXCLUDE)
install(FILES ${PROJECT_SOURCE_DIR}/docs/sablier.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
