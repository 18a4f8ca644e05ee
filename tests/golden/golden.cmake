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
