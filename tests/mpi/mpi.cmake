# SPDX-License-Identifier: MIT
# MPI ensembles (docs/cluster.md), included by tests/CMakeLists.txt. Label `mpi`.
# A golden case under `mpirun -n RANKS` must give the golden outputs byte for byte (check.sh);
# skipped (exit 77) when sablier is built without MPI or with the sanitizers.
set(MPI_CHECK_WORK ${CMAKE_CURRENT_BINARY_DIR}/mpi_work)
if(SABLIER_WITH_RENDER)
  set(MPI_CHECK_RENDER ON)
else()
  set(MPI_CHECK_RENDER OFF)
endif()
# Under the sanitizers the tests skip: OpenMPI's own allocations outlive MPI_Finalize and its
# memory hooks are not made for AddressSanitizer (the Release stages run them).
if(SABLIER_WITH_MPI AND SABLIER_SANITIZE)
  set(MPI_CHECK_BUILT SANITIZE)
elseif(SABLIER_WITH_MPI)
  set(MPI_CHECK_BUILT ON)
else()
  set(MPI_CHECK_BUILT OFF)
endif()
# the sweep on 3 ranks (2 workers: the bed, then the 2 members at once); the Shields scan on 2;
# the Brazil-nut samples (4 runs) on 3, slow as golden.bne_samples is
foreach(spec "sweep;3" "sediment_shields;2" "bne_samples;3")
  list(GET spec 0 case)
  list(GET spec 1 ranks)
  add_test(NAME mpi.${case}
           COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/check.sh $<TARGET_FILE:sablier> ${case} ${ranks}
                   ${MPI_CHECK_WORK} ${MPI_CHECK_RENDER} ${MPI_CHECK_BUILT}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(mpi.${case} PROPERTIES LABELS mpi SKIP_RETURN_CODE 77)
  if(case IN_LIST GOLDEN_SLOW)
    set_tests_properties(mpi.${case} PROPERTIES LABELS "mpi;slow")
  endif()
endforeach()
# `sablier ensemble` on 3 ranks: the tables of --jobs 1 (tests/mpi/ensemble.sh)
add_test(NAME mpi.ensemble
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/ensemble.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/tests/cli/ensemble_fall.scene ${MPI_CHECK_WORK}/ensemble
                 ${MPI_CHECK_BUILT}
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(mpi.ensemble PROPERTIES LABELS mpi SKIP_RETURN_CODE 77)
# SIGINT and SIGTERM to `mpirun -n 3 sablier ensemble`: every running member stops and saves its
# state (tests/mpi/signal.sh)
add_test(NAME mpi.signal
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/signal.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/tests/cli/ensemble_fall.scene ${MPI_CHECK_WORK}/signal
                 ${MPI_CHECK_BUILT}
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(mpi.signal PROPERTIES LABELS mpi SKIP_RETURN_CODE 77)
