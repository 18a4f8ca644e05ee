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

# The same cases with the hot loops forced to each instruction set (SABLIER_ISA; check_isa.sh
# skips a set this build or CPU lacks): the outputs must be the recorded bits on every path.
set(GOLDEN_ISA_CASES crater brazil_nut sediment discharge)
foreach(isa sse2 avx2 avx512)
  foreach(case ${GOLDEN_ISA_CASES})
    add_test(NAME golden.${case}.isa_${isa}
             COMMAND bash ${GOLDEN_DIR}/check_isa.sh ${isa} $<TARGET_FILE:sablier> ${case}
                     ${GOLDEN_WORK}/isa_${isa} ${GOLDEN_RENDER}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(golden.${case}.isa_${isa} PROPERTIES LABELS golden SKIP_RETURN_CODE 77)
    if(SABLIER_SANITIZE)
      set_tests_properties(golden.${case}.isa_${isa} PROPERTIES
        ENVIRONMENT "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp")
    endif()
  endforeach()
endforeach()
