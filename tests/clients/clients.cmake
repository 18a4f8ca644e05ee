# SPDX-License-Identifier: MIT
# Round trips of the per-grain dumps through real readers (docs/dumps.md), label `clients`:
# tests/clients/dump.scene runs once (fixture clients.run), then LAMMPS `lmp` reads every frame of
# its LAMMPS dumps with read_dump, VTK's vtkXMLPolyDataReader (Debian python3-vtk9, under
# /usr/bin/python3) reads every .vtp its .pvd files list, and `sablier export` of each stage's
# checkpoint equals that stage's last dump frame. A case whose reader is not installed is skipped
# (exit 77) with a message naming the package; scripts/setup.sh installs both.
find_program(SABLIER_CLIENT_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(SABLIER_CLIENT_PYTHON3)
  set(CLIENTS_DIR ${PROJECT_SOURCE_DIR}/tests/clients)
  set(CLIENTS_WORK ${CMAKE_CURRENT_BINARY_DIR}/clients_work)
  set(roundtrip ${SABLIER_CLIENT_PYTHON3} ${CLIENTS_DIR}/roundtrip.py)
  add_test(NAME clients.run
           COMMAND ${roundtrip} run $<TARGET_FILE:sablier> ${CLIENTS_DIR}/dump.scene ${CLIENTS_WORK})
  set_tests_properties(clients.run PROPERTIES LABELS clients FIXTURES_SETUP clients_dump
                       ENVIRONMENT "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/cli/lsan.supp")
  add_test(NAME clients.lammps_read_dump COMMAND ${roundtrip} lammps ${CLIENTS_WORK})
  add_test(NAME clients.vtk_reader COMMAND ${roundtrip} vtk ${CLIENTS_WORK})
  add_test(NAME clients.export_equals_dump
           COMMAND ${roundtrip} export $<TARGET_FILE:sablier> ${CLIENTS_WORK})
  foreach(case lammps_read_dump vtk_reader export_equals_dump)
    set_tests_properties(clients.${case} PROPERTIES LABELS clients FIXTURES_REQUIRED clients_dump
                         SKIP_RETURN_CODE 77 ENVIRONMENT
                         "PYTHONDONTWRITEBYTECODE=1;LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/cli/lsan.supp")
  endforeach()
else()
  message(STATUS "dump round trips off: no /usr/bin/python3")
endif()
