# SPDX-License-Identifier: MIT
# cmake -P bne_phase_field.cmake -DSABLIER=... -DSCENE=small.scene -DWORK=dir -DRENDER=ON|OFF
# `sablier run` on the small Brazil-nut box (4.9 periods, 4 phases) writes the phase-averaged
# velocity field: phase_field.csv (x,y,vx,vy,samples,solid_fraction, one row per node),
# phase_fields.csv (one block per phase), its summary in bne.json, no leftover .tmp, and with
# rendering the figure phase_field.png.
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${SABLIER} run ${SCENE} --out ${WORK}/out --quiet
                        --set stages.shake.time.end=19.5 --set bne.phase_field.phases=4
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run: exit ${rc}\n${err}")
endif()
file(READ ${WORK}/out/bne.json json)
string(JSON nx GET "${json}" phase_field nx)
string(JSON ny GET "${json}" phase_field ny)
string(JSON samples GET "${json}" phase_field samples)
string(JSON error GET "${json}" phase_field max_phase_error)
if(NOT samples EQUAL 16 OR error GREATER 0.00050001)
  message(FATAL_ERROR "bne.json phase_field: ${samples} samples (expected 4 cycles x 4 phases), "
                      "max phase error ${error} (expected <= dt/2)")
endif()
file(STRINGS ${WORK}/out/phase_field.csv rows)
list(GET rows 0 header)
list(LENGTH rows count)
math(EXPR expected "${nx} * ${ny} + 1")
if(NOT header STREQUAL "x,y,vx,vy,samples,solid_fraction" OR NOT count EQUAL expected)
  message(FATAL_ERROR "phase_field.csv: header `${header}`, ${count} lines (expected ${expected})")
endif()
file(STRINGS ${WORK}/out/phase_fields.csv rows)
list(GET rows 0 header)
list(LENGTH rows count)
math(EXPR expected "4 * ${nx} * ${ny} + 1")
if(NOT header STREQUAL "phase,x,y,vx,vy,samples,solid_fraction" OR NOT count EQUAL expected)
  message(FATAL_ERROR "phase_fields.csv: header `${header}`, ${count} lines (expected ${expected})")
endif()
file(GLOB tmp ${WORK}/out/*.tmp)
if(tmp)
  message(FATAL_ERROR "leftover temporary files: ${tmp}")
endif()
if(RENDER)
  if(NOT EXISTS ${WORK}/out/phase_field.png)
    message(FATAL_ERROR "no phase_field.png")
  endif()
  file(READ ${WORK}/out/phase_field.png magic LIMIT 8 HEX)
  if(NOT magic STREQUAL "89504e470d0a1a0a")
    message(FATAL_ERROR "phase_field.png is no PNG (${magic})")
  endif()
endif()
