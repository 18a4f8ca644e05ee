# SPDX-License-Identifier: MIT
# The Python module's tests (python/sablier, docs/python.md): each tests/python/test_*.py is one
# CTest entry python.<name>, run by Debian's interpreter /usr/bin/python3 (a python3 found
# earlier on PATH may not see Debian's python3-numpy) against this build's shared libraries.
# Registered only when that interpreter imports numpy, when the shared libraries are built, and
# not under the sanitizers (an instrumented library inside python would need libasan preloaded).
find_program(SABLIER_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
set(SABLIER_PYTHON_TESTS OFF)
if(SABLIER_PYTHON3 AND TARGET sim_shared AND NOT SABLIER_SANITIZE)
  execute_process(COMMAND ${SABLIER_PYTHON3} -c "import numpy" RESULT_VARIABLE numpy_status
                  OUTPUT_QUIET ERROR_QUIET)
  if(numpy_status EQUAL 0)
    set(SABLIER_PYTHON_TESTS ON)
  else()
    message(STATUS "Python tests off: ${SABLIER_PYTHON3} cannot import numpy (python3-numpy)")
  endif()
endif()

if(SABLIER_PYTHON_TESTS)
  file(GLOB files CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/python/test_*.py)
  foreach(file ${files})
    get_filename_component(name ${file} NAME_WE)
    string(REGEX REPLACE "^test_" "" short ${name})
    add_test(NAME python.${short} COMMAND ${SABLIER_PYTHON3} -m unittest -v ${name}
             WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/python)
    set_tests_properties(python.${short} PROPERTIES LABELS python
      ENVIRONMENT "SABLIER_LIB_DIR=${PROJECT_BINARY_DIR};SABLIER_EXECUTABLE=$<TARGET_FILE:sablier>;SABLIER_SOURCE_DIR=${PROJECT_SOURCE_DIR};PYTHONDONTWRITEBYTECODE=1")
  endforeach()
endif()

# The offline virtual-environment install of docs/python.md, then an in-process stage run, the
# coarse-grained stress and a figure from the installed module (tests/python/venv_install.sh).
# Needs Debian's python3-venv and python3-setuptools (scripts/setup.sh).
if(SABLIER_PYTHON_TESTS AND TARGET scene_shared)
  execute_process(COMMAND ${SABLIER_PYTHON3} -c "import venv, ensurepip, setuptools"
                  RESULT_VARIABLE venv_status OUTPUT_QUIET ERROR_QUIET)
  if(venv_status EQUAL 0)
    add_test(NAME python.venv_install
             COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/python/venv_install.sh ${PROJECT_SOURCE_DIR}
                     ${PROJECT_BINARY_DIR})
    set_tests_properties(python.venv_install PROPERTIES LABELS python)
  else()
    message(STATUS "python.venv_install off: ${SABLIER_PYTHON3} lacks venv or setuptools "
                   "(python3-venv, python3-setuptools)")
  endif()
endif()
