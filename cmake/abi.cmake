# SPDX-License-Identifier: MIT
# The ABI of the public shared libraries (docs/install.md, "ABI"). While the version is 0.x a
# minor release may change the API, so the SONAME carries the minor: libsablier-sim.so.0.1 for
# 0.1.z (from 1.0 on, the major alone). Each public library exports exactly the functions its
# public headers declare (a linker version script made from them, below); everything else,
# internal sim_ and render_ helpers included, is local. tests/install/abi.sh compares the
# exported symbols with the lists recorded in tests/install/abi/ (Debian symbols files).
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(SABLIER_SOVERSION "0.${PROJECT_VERSION_MINOR}")
else()
  set(SABLIER_SOVERSION "${PROJECT_VERSION_MAJOR}")
endif()

# sablier_export_headers(TARGET PREFIX HEADER...): TARGET's version script exports the PREFIX*
# functions that the HEADERs declare (comments removed first), and nothing else.
function(sablier_export_headers target prefix)
  set(names "")
  foreach(header ${ARGN})
    file(READ ${header} text)
    string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
    string(REGEX REPLACE "//[^\n]*" "" text "${text}")
    string(REGEX MATCHALL "${prefix}[A-Za-z0-9_]*[ \t\n]*\\(" found "${text}")
    list(APPEND names ${found})
    set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${header})
  endforeach()
  list(TRANSFORM names REPLACE "[ \t\n]*\\($" "")
  list(REMOVE_DUPLICATES names)
  list(SORT names)
  list(JOIN names ";\n    " names)
  set(map ${PROJECT_BINARY_DIR}/abi/${target}.map)
  file(CONFIGURE OUTPUT ${map} CONTENT "{\n  global:\n    ${names};\n  local:\n    *;\n};\n" @ONLY)
  target_link_options(${target} PRIVATE "LINKER:--version-script=${map}")
  set_property(TARGET ${target} APPEND PROPERTY LINK_DEPENDS ${map})
endfunction()
