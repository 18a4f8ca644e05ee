# SPDX-License-Identifier: MIT
# cmake -P expect.cmake -DSABLIER=... -DARGS="a|b|c" -DRC=0 [-DOUT=regex] [-DERR=regex]
# [-DWORKDIR=dir] [-DNOT_ERR=regex]: runs `sablier a b c`, checks the exit status and matches
# stdout / stderr (NOT_ERR: stderr must not match).
string(REPLACE "|" ";" args "${ARGS}")
if(NOT WORKDIR)
  set(WORKDIR ".")
endif()
execute_process(COMMAND ${SABLIER} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err WORKING_DIRECTORY ${WORKDIR})
if(NOT rc EQUAL RC)
  message(FATAL_ERROR "sablier ${args}: exit ${rc}, expected ${RC}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED OUT AND NOT out MATCHES "${OUT}")
  message(FATAL_ERROR "sablier ${args}: stdout does not match `${OUT}`:\n${out}")
endif()
if(DEFINED ERR AND NOT err MATCHES "${ERR}")
  message(FATAL_ERROR "sablier ${args}: stderr does not match `${ERR}`:\n${err}")
endif()
if(DEFINED NOT_ERR AND err MATCHES "${NOT_ERR}")
  message(FATAL_ERROR "sablier ${args}: stderr matches `${NOT_ERR}`:\n${err}")
endif()
