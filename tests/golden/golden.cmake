# SPDX-License-Identifier: MIT
# Golden-output tests (tests/golden/README.md), included by tests/CMakeLists.txt. Label `golden`.
# One test per case folder tests/golden/<case>/: run the case (cases.sh) with this build's
# `sablier` into the build tree and compare with the recorded outputs (compare.sh).
set(GOLDEN_DIR ${CMAKE_CURRENT_LIST_DIR})
set(GOLDEN_WORK ${CMAKE_CURRENT_BINARY_DIR}/golden_work)
if(SABLIER_WITH_RENDER)
  set(GOLDEN_RENDER ON)
else()
  set(GOLDEN_RENDER OFF)
endif()
# cases above 60 s under AddressSanitizer (2 shared cores): label slow, skipped by the sanitizer
# stage of .ci/run
set(GOLDEN_SLOW bne_samples study)
file(GLOB golden_entries CONFIGURE_DEPENDS ${GOLDEN_DIR}/*)
foreach(entry ${golden_entries})
  if(IS_DIRECTORY ${entry})
    get_filename_component(case ${entry} NAME)
    add_test(NAME golden.${case}
             COMMAND bash ${GOLDEN_DIR}/check.sh $<TARGET_FILE:sablier> ${case} ${GOLDEN_WORK}
                     ${GOLDEN_RENDER}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    if(case IN_LIST GOLDEN_SLOW)
      set_tests_properties(golden.${case} PROPERTIES LABELS "golden;slow")
    else()
      set_tests_properties(golden.${case} PROPERTIES LABELS golden)
    endif()
    if(SABLIER_SANITIZE)
      set_tests_properties(golden.${case} PROPERTIES
        ENVIRONMENT "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp")
    endif()
  endif()
endforeach()

# A variant of golden case CASE: test NAME runs SCRIPT (check_isa.sh, check_threads.sh) with
# ARG before check.sh's arguments, into WORK; SCRIPT exits 77 to skip.
function(golden_variant name script arg case work)
  add_test(NAME ${name}
           COMMAND bash ${GOLDEN_DIR}/${script} ${arg} $<TARGET_FILE:sablier> ${case} ${work}
                   ${GOLDEN_RENDER}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(${name} PROPERTIES LABELS golden SKIP_RETURN_CODE 77)
  if(SABLIER_SANITIZE)
    set_tests_properties(${name} PROPERTIES
      ENVIRONMENT "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp")
  endif()
endfunction()

# The same cases with the hot loops forced to each instruction set (SABLIER_ISA; check_isa.sh
# skips a set this build or CPU lacks): the outputs must be the recorded bits on every path.
set(GOLDEN_ISA_CASES crater brazil_nut sediment discharge)
foreach(isa sse2 avx2 avx512)
  foreach(case ${GOLDEN_ISA_CASES})
    golden_variant(golden.${case}.isa_${isa} check_isa.sh ${isa} ${case} ${GOLDEN_WORK}/isa_${isa})
  endforeach()
endforeach()

# The `sablier run` cases on 1, 2, 3 and 8 threads, and with the count switched every 50 steps
# (check_threads.sh): the outputs must be the recorded bits on any count.
set(GOLDEN_THREAD_CASES crater brazil_nut)
foreach(threads 1 2 3 8 switch)
  foreach(case ${GOLDEN_THREAD_CASES})
    golden_variant(golden.${case}.threads_${threads} check_threads.sh ${threads} ${case}
                   ${GOLDEN_WORK}/threads_${threads})
  endforeach()
endforeach()
