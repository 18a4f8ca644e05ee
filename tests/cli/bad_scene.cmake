# SPDX-License-Identifier: MIT
# cmake -P bad_scene.cmake -DSABLIER=... -DSCENE=/abs/path/x.scene -DWORK=dir
# A broken scene: `check` and `run` exit 2, stderr names exactly the file:line given by the
# scene's first line `# expect: FILE:LINE`, and `run` creates no output folder.
file(STRINGS ${SCENE} first LIMIT_COUNT 1)
if(NOT first MATCHES "^# expect: ([^ ]+:[0-9]+)$")
  message(FATAL_ERROR "${SCENE}: first line must be `# expect: FILE:LINE`")
endif()
set(expect "/${CMAKE_MATCH_1}:")
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
foreach(command check run)
  execute_process(COMMAND ${SABLIER} ${command} ${SCENE} RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err WORKING_DIRECTORY ${WORK})
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "sablier ${command} ${SCENE}: exit ${rc}, expected 2\n${err}")
  endif()
  string(FIND "${err}" "${expect}" at)
  if(at LESS 0)
    message(FATAL_ERROR "sablier ${command} ${SCENE}: stderr lacks `${expect}`:\n${err}")
  endif()
  file(GLOB left ${WORK}/*)
  if(left)
    message(FATAL_ERROR "sablier ${command} ${SCENE} created ${left}")
  endif()
endforeach()
