# SPDX-License-Identifier: MIT
# Run at every build (cmake -P): writes OUT (revision.h) with SABLIER_REVISION, the git revision of
# SOURCE ("<hash>" or "<hash>-dirty"), or "unknown" outside a repository; the file is rewritten
# only when the revision changed, so an unchanged tree recompiles nothing.
set(revision "unknown")
find_program(GIT git)
if(GIT AND EXISTS "${SOURCE}/.git")
  execute_process(COMMAND ${GIT} -C "${SOURCE}" rev-parse --short=12 HEAD
                  OUTPUT_VARIABLE hash OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc
                  ERROR_QUIET)
  if(rc EQUAL 0 AND hash)
    set(revision "${hash}")
    execute_process(COMMAND ${GIT} -C "${SOURCE}" diff --quiet HEAD -- RESULT_VARIABLE dirty
                    ERROR_QUIET)
    if(NOT dirty EQUAL 0)
      set(revision "${hash}-dirty")
    endif()
  endif()
endif()
set(text "/* made by cmake/revision.cmake */\n#define SABLIER_REVISION \"${revision}\"\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
