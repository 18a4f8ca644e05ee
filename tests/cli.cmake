# SPDX-License-Identifier: MIT
# CLI tests of `sablier` (included by tests/CMakeLists.txt). Label `cli`.
set(CLI_DIR ${PROJECT_SOURCE_DIR}/tests/cli)
set(CLI_WORK ${CMAKE_CURRENT_BINARY_DIR}/cli_work)
set(CLI_TINY ${PROJECT_SOURCE_DIR}/scenes/validation/drop_elastic.scene)

function(sablier_cli_test name args rc)
  cmake_parse_arguments(T "" "OUT;ERR;NOT_ERR" "" ${ARGN})
  set(defs -DSABLIER=$<TARGET_FILE:sablier> "-DARGS=${args}" -DRC=${rc})
  if(DEFINED T_OUT)
    list(APPEND defs "-DOUT=${T_OUT}")
  endif()
  if(DEFINED T_ERR)
    list(APPEND defs "-DERR=${T_ERR}")
  endif()
  if(DEFINED T_NOT_ERR)
    list(APPEND defs "-DNOT_ERR=${T_NOT_ERR}")
  endif()
  add_test(NAME cli.${name} COMMAND ${CMAKE_COMMAND} ${defs} -P ${CLI_DIR}/expect.cmake
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(cli.${name} PROPERTIES LABELS cli)
endfunction()

# help, version, usage errors
sablier_cli_test(help "--help" 0 OUT "usage: sablier COMMAND")
foreach(command run check diff render export)
  sablier_cli_test(help_${command} "${command}|--help" 0 OUT "usage: sablier ${command}")
endforeach()
# docs/cli.md and the man page against every command's --help (tests/cli/cli_docs.py): each
# command's option table names exactly the options its --help names, the man page names them all,
# and --help, the man page and docs/cli.md give one list of exit statuses, per command too
find_program(SABLIER_PYTHON3 python3)
if(SABLIER_PYTHON3)
  add_test(NAME cli.docs_match_help
           COMMAND ${SABLIER_PYTHON3} ${CLI_DIR}/cli_docs.py $<TARGET_FILE:sablier>
                   ${PROJECT_SOURCE_DIR}/docs/cli.md ${PROJECT_SOURCE_DIR}/docs/sablier.1)
  set_tests_properties(cli.docs_match_help PROPERTIES LABELS cli)
endif()
# the scenes written in d = g = 1 (column, chute) name their own units in summary.json, the CSV
# headers and the figures' time stamps and colour bars, never SI (tests/cli/units_outputs.sh)
if(SABLIER_WITH_RENDER)
  find_program(SABLIER_PDFTOTEXT pdftotext)
  foreach(kind summary csv figures)
    if(kind STREQUAL "figures" AND NOT SABLIER_PDFTOTEXT)
      continue()
    endif()
    add_test(NAME cli.units_outputs_${kind}
             COMMAND bash ${CLI_DIR}/units_outputs.sh $<TARGET_FILE:sablier>
                     ${CLI_WORK}/units_outputs_${kind} ${kind}
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    set_tests_properties(cli.units_outputs_${kind} PROPERTIES LABELS cli)
  endforeach()
endif()
sablier_cli_test(version "--version" 0 OUT "sablier [0-9]+\\.[0-9]+\\.[0-9]+\nsim [0-9.]+\nlibconfig 1\\.[0-9.]+\nrender: ")
sablier_cli_test(no_command "" 2 ERR "usage: sablier")
sablier_cli_test(unknown_command "frobnicate" 2 ERR "unknown command `frobnicate`")
sablier_cli_test(unknown_option "check|${CLI_TINY}|--frob" 2 ERR "unknown option --frob")
sablier_cli_test(run_no_scene "run" 2 ERR "missing SCENE")
sablier_cli_test(run_bad_threads "run|${CLI_TINY}|--threads|0" 2 ERR "--threads")
sablier_cli_test(run_bad_progress_every "run|${CLI_TINY}|--progress-every|-1" 2
                 ERR "--progress-every needs seconds >= 0, got -1")
sablier_cli_test(missing_scene_file "check|no_such.scene" 2 ERR "no_such.scene: cannot read")

# --set overrides, visible in `check`
sablier_cli_test(set_dt "check|${CLI_TINY}|--set|time.dt=2e-5" 0 OUT "time step +2e-05 s")
sablier_cli_test(set_species_index "check|${CLI_TINY}|--set|species.0.k_n=2e6" 0
                 OUT "k_n 2e\\+06")
sablier_cli_test(set_species_bracket "check|${CLI_TINY}|--set|species[0].density=1000" 0
                 OUT "density 1000,")
sablier_cli_test(set_stage_by_name
                 "check|${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene|--set|stages.collapse.time.end=1.5"
                 0 OUT "stage collapse: [^\n]*time.end 1.5 s")
sablier_cli_test(set_effects_array
                 "check|${CLI_TINY}|--set|effects=[friction]|--set|species.0.mu=0.3|--set|species.0.gamma_s=1"
                 0 OUT "effects +friction")
sablier_cli_test(set_unknown_path "check|${CLI_TINY}|--set|nope.key=1" 2
                 ERR "--set nope.key: unknown key `nope`")
sablier_cli_test(set_bad_value "check|${CLI_TINY}|--set|time.dt=fast" 2
                 ERR "--set time.dt: `fast` is not a number")
sablier_cli_test(set_bad_index "check|${CLI_TINY}|--set|species.3.k_n=1" 2
                 ERR "--set species.3.k_n: no such element")
sablier_cli_test(set_no_value "check|${CLI_TINY}|--set|time.dt" 2 ERR "--set time.dt: expected KEY=VALUE")
sablier_cli_test(set_undeclared_effect "check|${CLI_TINY}|--set|species.0.mu=0.5" 2
                 ERR "--set species.0.mu: `mu` needs effect \"friction\"")
sablier_cli_test(set_int_key "check|${CLI_TINY}|--set|seed=1.5" 2 ERR "--set seed: `seed` must be an integer")

# a stage's own `movie` wins over output.movie's list (quick.scene lists collapse)
sablier_cli_test(stage_movie_off
                 "check|${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene|--set|stages.collapse.movie=false"
                 0 OUT "stage deposit: [^\n]*, movie[^\n]*\n.*stage collapse: [^\n]*0.5 s[)]\n")
sablier_cli_test(stage_movie_listed "check|${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene" 0
                 OUT "stage collapse: [^\n]*, movie[^\n]*\n")
# the README demo's collapse plays at a documented speed (docs/figures.md#movies): a quarter of
# real time, so the ~1 s collapse is a ~4 s clip
sablier_cli_test(quick_movie_speed "check|${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene" 0
                 OUT "stage collapse: [^\n]*movie: a frame every 0.01 s, 0.25 s simulated per s of video\n")

# progress without a terminal (ctest's pipe: a batch job's log): one whole line per
# --progress-every seconds of wall time with the stage, simulated time, rate and ETA; none with
# --quiet, none in a run shorter than the default minute
set(progress_run "run|${CLI_TINY}|--set|time.end=40")
sablier_cli_test(run_progress_batch "${progress_run}|--out|${CLI_WORK}/progress|--progress-every|0.02" 0
                 ERR "(^|\n)sablier: progress: stage run [(]1/1[)]  t = [0-9.e+-]+ / 40 s  [0-9.e+-]+ steps/s, [0-9.e+-]+ s simulated per s  ETA [0-9]+ s\n(sablier: progress: [^\n]*\n)*sablier: stage run: 40 s simulated"
                 NOT_ERR "\r")
sablier_cli_test(run_progress_quiet "${progress_run}|--out|${CLI_WORK}/progress_quiet|--progress-every|0.02|--quiet" 0
                 ERR "sablier: stage run: 40 s simulated" NOT_ERR "progress:")
sablier_cli_test(run_progress_default "${progress_run}|--out|${CLI_WORK}/progress_default" 0
                 ERR "sablier: stage run: 40 s simulated" NOT_ERR "progress:")

# a driver that runs its members without rendering on purpose does not warn "not built"
sablier_cli_test(sediment_no_render_warning
                 "sediment|${PROJECT_SOURCE_DIR}/scenes/sediment/viscous.scene|--shields|0.1|--jobs|1|--quiet|--out|${CLI_WORK}/sediment_no_render|--set|stages.settle.time.end=0.2|--set|stages.flow.time.end=0.2"
                 0 ERR "stage flow: 0.2 sqrt.d/g. simulated" NOT_ERR "rendering is not built")

# every shipped scene passes `check`
file(GLOB_RECURSE shipped CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/scenes/*.scene)
foreach(scene ${shipped})
  file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR}/scenes ${scene})
  string(REGEX REPLACE "\\.scene$" "" rel ${rel})
  string(REPLACE "/" "." rel ${rel})
  sablier_cli_test(check.${rel} "check|${scene}" 0 OUT "\nok\n")
endforeach()

# every broken scene: exit 2, exact file:line, no output folder
file(GLOB broken CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/scenes_bad/*.scene)
foreach(scene ${broken})
  get_filename_component(name ${scene} NAME_WE)
  add_test(NAME cli.bad.${name}
           COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier> -DSCENE=${scene}
                   -DWORK=${CLI_WORK}/bad_${name} -P ${CLI_DIR}/bad_scene.cmake)
  set_tests_properties(cli.bad.${name} PROPERTIES LABELS cli)
endforeach()

# a run writes its outputs; render and diff work on them
add_test(NAME cli.run_outputs
         COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier> -DSCENE=${CLI_TINY}
                 -DWORK=${CLI_WORK}/run_outputs -DRENDER=${SABLIER_WITH_RENDER}
                 -P ${CLI_DIR}/run_outputs.cmake)
set_tests_properties(cli.run_outputs PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
# the shaken small box writes its phase-averaged velocity field and figure (bne.phase_field)
add_test(NAME cli.bne_phase_field
         COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                 -DSCENE=${PROJECT_SOURCE_DIR}/scenes/brazil_nut/small.scene
                 -DWORK=${CLI_WORK}/bne_phase_field -DRENDER=${SABLIER_WITH_RENDER}
                 -P ${CLI_DIR}/bne_phase_field.cmake)
set_tests_properties(cli.bne_phase_field PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
# print sizes of figures: style presets, size + dpi, pixels; PNG pHYs, PDF page
if(SABLIER_WITH_RENDER)
  add_test(NAME cli.print_figures
           COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                   -DSCENE=${CLI_DIR}/print_figures.scene -DWORK=${CLI_WORK}/print_figures
                   -P ${CLI_DIR}/print_figures.cmake)
  set_tests_properties(cli.print_figures PROPERTIES LABELS cli
                       ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
  # two identical runs: the same PNG, PDF and SVG bytes, no absolute path in any output, the date
  # only from SOURCE_DATE_EPOCH
  add_test(NAME cli.reproducible
           COMMAND bash ${CLI_DIR}/reproducible.sh $<TARGET_FILE:sablier>
                   ${CLI_DIR}/reproducible.scene ${CLI_WORK}/reproducible)
  set_tests_properties(cli.reproducible PROPERTIES LABELS cli
                       ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
endif()
# a run that blows up: exit 1, message with step and grain, last good state saved
add_test(NAME cli.run_unstable
         COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                 "-DARGS=run|${CLI_TINY}|--quiet|--out|${CLI_WORK}/unstable|--set|guard.max_overlap=1e-4"
                 -DRC=1 "-DERR=simulation failed at step [0-9]+ .*grain 0.*likely cause: time step [^;]* of the contact time.*run.last_good.state"
                 -P ${CLI_DIR}/expect.cmake)
set_tests_properties(cli.run_unstable PROPERTIES LABELS cli)
if(NOT SABLIER_WITH_RENDER)
  sablier_cli_test(diff_not_built "diff|a.png|b.png" 2 ERR "rendering is not built")
  sablier_cli_test(render_not_built "render|a.state|-o|a.png" 2 ERR "rendering is not built")
endif()

# plots at print size, in a second format, byte-identical
add_test(NAME cli.plot_format
         COMMAND bash ${CLI_DIR}/plot_format.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/measure/column.scene ${CLI_WORK}/plot_format)
set_tests_properties(cli.plot_format PROPERTIES LABELS cli)

# SIGINT/SIGTERM, stale outputs, foreign folders and provenance
add_test(NAME cli.interrupt
         COMMAND bash ${CLI_DIR}/interrupt.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene ${CLI_TINY} ${CLI_WORK}/interrupt)
set_tests_properties(cli.interrupt PROPERTIES LABELS cli)
add_test(NAME cli.sweep_inputs
         COMMAND bash ${CLI_DIR}/sweep_inputs.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/crater/small.scene ${CLI_WORK}/sweep_inputs)
set_tests_properties(cli.sweep_inputs PROPERTIES LABELS cli)
# a sweep from --vary alone: crater_height's x axis names the key with its unit, a species key
# (the species table) or a scalar key of the scene (time.dt: the `time` group's table)
add_test(NAME cli.sweep_vary_units
         COMMAND bash ${CLI_DIR}/sweep_vary_units.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/crater/small.scene ${CLI_WORK}/sweep_vary_units
                 ${PROJECT_SOURCE_DIR}/tests/lint/figure_lint.py species.0.mu=0.1,0.5
                 "species.0.mu (1)")
set_tests_properties(cli.sweep_vary_units PROPERTIES LABELS cli)
add_test(NAME cli.sweep_vary_time_units
         COMMAND bash ${CLI_DIR}/sweep_vary_units.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/crater/small.scene ${CLI_WORK}/sweep_vary_time_units
                 ${PROJECT_SOURCE_DIR}/tests/lint/figure_lint.py time.dt=5e-5,4e-5 "time.dt (s)")
set_tests_properties(cli.sweep_vary_time_units PROPERTIES LABELS cli)
add_test(NAME cli.sediment_alias
         COMMAND bash ${CLI_DIR}/sediment_alias.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/sediment/viscous.scene ${CLI_WORK}/sediment_alias)
set_tests_properties(cli.sediment_alias PROPERTIES LABELS cli)
add_test(NAME cli.include_fifo
         COMMAND bash ${CLI_DIR}/include_fifo.sh $<TARGET_FILE:sablier> ${CLI_WORK}/include_fifo)
set_tests_properties(cli.include_fifo PROPERTIES LABELS cli)
add_test(NAME cli.late_checks
         COMMAND bash ${CLI_DIR}/late_checks.sh $<TARGET_FILE:sablier> ${CLI_TINY}
                 ${PROJECT_SOURCE_DIR}/scenes/brazil_nut/small.scene ${CLI_WORK}/late_checks)
set_tests_properties(cli.late_checks PROPERTIES LABELS cli TIMEOUT 120)
# every input file refused unless regular, before it is read: a FIFO never blocks
add_test(NAME cli.input_fifo
         COMMAND bash ${CLI_DIR}/input_fifo.sh $<TARGET_FILE:sablier> ${CLI_WORK}/input_fifo)
set_tests_properties(cli.input_fifo PROPERTIES LABELS cli)
# outputs: regular files through a temporary name, never a link or a device; a full disk
# exits 3. The shim stands in for a full disk without mounting one.
add_library(full_disk_shim MODULE ${CLI_DIR}/full_disk_shim.c)
target_link_libraries(full_disk_shim PRIVATE ${CMAKE_DL_LIBS})
add_test(NAME cli.output_files
         COMMAND bash ${CLI_DIR}/output_files.sh $<TARGET_FILE:sablier> ${CLI_TINY}
                 $<TARGET_FILE:full_disk_shim> ${CLI_WORK}/output_files)
set_tests_properties(cli.output_files PROPERTIES LABELS cli)
# the output folder is a sandbox: the manifest lists what the run wrote; its cleanup follows no
# link and removes only regular files inside the folder
add_test(NAME cli.manifest_sandbox
         COMMAND bash ${CLI_DIR}/manifest_sandbox.sh $<TARGET_FILE:sablier> ${CLI_TINY}
                 ${CLI_WORK}/manifest_sandbox)
set_tests_properties(cli.manifest_sandbox PROPERTIES LABELS cli)
add_test(NAME cli.remove_ids_missing
         COMMAND bash ${CLI_DIR}/remove_ids.sh $<TARGET_FILE:sablier> ${CLI_TINY}
                 ${CLI_WORK}/remove_ids)
set_tests_properties(cli.remove_ids_missing PROPERTIES LABELS cli)
add_test(NAME cli.resume
         COMMAND bash ${CLI_DIR}/resume.sh $<TARGET_FILE:sablier> ${CLI_DIR}/resume.scene ${CLI_TINY}
                 ${CLI_WORK}/resume)
set_tests_properties(cli.resume PROPERTIES LABELS cli)
# --resume of each experiment family's scene (and the crater demo's per-grain dump), reduced with
# --set to run in seconds: the outputs of a lost and of an interrupted run, continued, are the
# uninterrupted run's (tests/cli/resume.sh --outputs)
set(RESUME_QUIET "output.movie=[]")
set(RESUME_crater scenes/crater/quick.scene grains.rain.max_count=300 stages.deposit.time.end=0.6
    stages.collapse.time.end=0.6 stages.collapse.dump.every=0.05 output.checkpoint_every=0.2
    output.figures.5.at=0.5)
set(RESUME_bne scenes/brazil_nut/small.scene stages.settle.time.end=3 stages.shake.time.end=10
    bne.phase_field.phases=4 output.checkpoint_every=6)
set(RESUME_sediment scenes/sediment/viscous.scene stages.settle.time.end=1.5
    stages.flow.time.end=2 output.checkpoint_every=0.8)
set(RESUME_surface scenes/drum/drum.scene stages.settle.time.end=3 stages.rotate.time.end=6
    surface.after=2 output.checkpoint_every=2.5)
set(RESUME_measures scenes/measure/column.scene grains.rain.max_count=150 stages.rain.time.end=4
    output.checkpoint_every=1.5)
# (discharge keeps nothing between steps of a run: its hooks act in the phases of `sablier discharge`
# and `study` only, and its scenes run plain stages, as cli.resume's does)
foreach(family crater bne sediment surface measures)
  list(GET RESUME_${family} 0 scene)
  list(SUBLIST RESUME_${family} 1 -1 sets)
  set(args)
  foreach(set IN LISTS sets RESUME_QUIET)
    list(APPEND args --set ${set})
  endforeach()
  add_test(NAME cli.resume_${family}
           COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                   ${PROJECT_SOURCE_DIR}/${scene} ${CLI_WORK}/resume_${family} ${args})
  set_tests_properties(cli.resume_${family} PROPERTIES LABELS cli)
endforeach()
add_test(NAME cli.cadence_huge
         COMMAND bash ${CLI_DIR}/cadence.sh $<TARGET_FILE:sablier> ${CLI_TINY} ${CLI_WORK}/cadence)
set_tests_properties(cli.cadence_huge PROPERTIES LABELS cli)
# a measure's windows at exact multiples of its cadence with a step that divides nothing, and a
# a servo wall from a scene: its time scale in `check`, walls.csv and the steady mean
# (tests/cli/servo_lid.sh)
add_test(NAME cli.servo_lid
         COMMAND bash ${CLI_DIR}/servo_lid.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/servo_lid.scene ${CLI_WORK}/servo_lid)
set_tests_properties(cli.servo_lid PROPERTIES LABELS cli)
# a rough piston (`bodies`: a row of fixed grains moving as one rigid body) falling on a bed rests
# at the balance of its weight, and one held by a servo keeps its target stress, both within 1 %
# over the window of walls.csv's means (tests/cli/rough_piston.sh)
add_test(NAME cli.wall_rough_piston
         COMMAND bash ${CLI_DIR}/rough_piston.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/rough_piston.scene ${CLI_WORK}/rough_piston)
add_test(NAME cli.servo_rough_piston
         COMMAND bash ${CLI_DIR}/rough_piston.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/rough_piston_servo.scene ${CLI_WORK}/rough_piston_servo --servo)
set_tests_properties(cli.wall_rough_piston cli.servo_rough_piston PROPERTIES LABELS cli)
# the rough piston's run lost after a checkpoint, and interrupted, then resumed: every output
# byte for byte as the uninterrupted run's (tests/cli/resume.sh --outputs)
add_test(NAME cli.resume_rough_piston
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/rough_piston.scene ${CLI_WORK}/resume_rough_piston
                 --set stages.press.time.end=1.0 --set output.walls.window=[0.5,1.0]
                 --set output.checkpoint_every=0.4)
set_tests_properties(cli.resume_rough_piston PROPERTIES LABELS cli)
# the servo's damping bound at run time: the 1.98 m lid (force 4000 N, gain 1e-3, gamma_n 200)
# holds its mean within 1 % of the target under the implicit law whether sampled every 10 or every
# 2 steps, and under the explicit law flips, told once on stderr and counted in summary.json
# (tests/cli/servo_flip.sh)
add_test(NAME cli.servo_flip
         COMMAND bash ${CLI_DIR}/servo_flip.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/servo_flip.scene ${CLI_WORK}/servo_flip)
set_tests_properties(cli.servo_flip PROPERTIES LABELS cli)
# a grain body's servo in `check`: its time scale and damping feedback, named by its group, and
# the warning at its file:line when a row of grains along it would flip it (stderr, unbuffered,
# comes first)
# (tests/cli/rough_piston_servo.scene with a gain 5 times its own)
add_test(NAME cli.servo_body_check
         COMMAND $<TARGET_FILE:sablier> check ${CLI_DIR}/rough_piston_servo.scene
                 --set bodies.0.servo.gain=1e-3)
set_tests_properties(cli.servo_body_check PROPERTIES LABELS cli PASS_REGULAR_EXPRESSION
  "rough_piston_servo.scene:11: warning: body piston's servo flips its speed every step(.|\n)*body piston servo +target stress 2000, time scale tau 0.000920419 s[^\n]*damping feedback 0.1 per contact")
# a rough piston built by a stage's `add` (group "piston") on a deposited bed: its servo holds
# 2000 N/m within 1 %, trace.csv names the added grains, the same bytes on 1, 2, 3 and 8 threads
# (tests/cli/added_piston.sh); lost after a checkpoint taken once the piston moves, and
# interrupted, then resumed: every output byte for byte (tests/cli/resume.sh --outputs)
add_test(NAME cli.added_piston
         COMMAND bash ${CLI_DIR}/added_piston.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/added_piston.scene ${CLI_WORK}/added_piston)
add_test(NAME cli.resume_added_piston
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/added_piston.scene ${CLI_WORK}/resume_added_piston
                 --set stages.press.time.end=1.0 --set output.walls.window=[1.2,1.8]
                 --set output.checkpoint_every=0.6)
set_tests_properties(cli.added_piston cli.resume_added_piston PROPERTIES LABELS cli)
# the servo's damping bound: a lid whose full row of grains would flip its speed is warned about
# at its file:line, with the gain that keeps a row stable (tests/scenes_bad/servo_damping_gain.scene:
# one contact already flips it, refused)
add_test(NAME cli.servo_damping_warning COMMAND $<TARGET_FILE:sablier> check ${CLI_DIR}/servo_lid.scene
         --set "walls.3.servo.damping=\"explicit\"")
set_tests_properties(cli.servo_damping_warning PROPERTIES LABELS cli PASS_REGULAR_EXPRESSION
  "servo_lid.scene:15: warning: wall 3's servo flips its speed every step once 10 grains touch it[^\n]*gain below 0.000454545")
# the scenes of docs/experiments.md for controlled boundaries (biaxial compression, Janssen silo,
# plane shear by the base and by the lid, impact with its depth in time) load and a shortened run of each shows its physics
# (tests/cli/lab_scenes.sh)
foreach(case biaxial janssen plane_shear plane_shear_lid impact)
  add_test(NAME cli.lab_scenes.${case}
           COMMAND bash ${CLI_DIR}/lab_scenes.sh $<TARGET_FILE:sablier> ${PROJECT_SOURCE_DIR}
                   ${CLI_WORK}/lab_scenes_${case} ${case})
  set_tests_properties(cli.lab_scenes.${case} PROPERTIES LABELS cli)
endforeach()
# their analyses (scripts/experiments/) on small studies (tests/cli/lab_scripts.sh); 77: no numpy
add_test(NAME cli.lab_scripts
         COMMAND bash ${CLI_DIR}/lab_scripts.sh $<TARGET_FILE:sablier> ${PROJECT_SOURCE_DIR}
                 ${CLI_WORK}/lab_scripts)
set_tests_properties(cli.lab_scripts PROPERTIES LABELS cli SKIP_RETURN_CODE 77 TIMEOUT 300)
# the servo lid's run lost after a checkpoint, and interrupted, then resumed: every output (the
# .state with the lid's offset and speed, walls.csv, summary.json's wall means) byte for byte as
# the uninterrupted run's (tests/cli/resume.sh --outputs)
add_test(NAME cli.resume_servo
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/servo_lid.scene ${CLI_WORK}/resume_servo --set stages.press.time.end=1.5
                 --set output.walls.window=[1.0,1.5] --set output.checkpoint_every=0.7)
set_tests_properties(cli.resume_servo PROPERTIES LABELS cli)
# the explicit 1.98 m lid, flipping, lost after a checkpoint taken while it flips, and
# interrupted, then resumed: every output byte for byte, summary.json's servo_flips included (the
# flip counters are in the .state's footer)
add_test(NAME cli.resume_servo_flip
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/servo_flip.scene ${CLI_WORK}/resume_servo_flip
                 --set "walls.3.servo.damping=\"explicit\"" --set stages.press.time.end=2.5
                 --set output.walls.window=[2.0,2.5] --set output.checkpoint_every=2.2)
set_tests_properties(cli.resume_servo_flip PROPERTIES LABELS cli)
# two motions running when a periodic checkpoint is taken (the lid pressed through `hold` too,
# the side wall shearing): the resumed world sets their clocks one after the other, and a wall
# placed by a clock not yet set must not count in the list's shift (the resumed .state's list
# bookkeeping, build step and reference positions, equal the uninterrupted run's)
add_test(NAME cli.resume_motions
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/motion_clock.scene ${CLI_WORK}/resume_motions
                 --set output.checkpoint_every=0.3 --set stages.hold.motions=["press"])
set_tests_properties(cli.resume_motions PROPERTIES LABELS cli)
# the lid of plane_shear_lid.scene, a servo that also follows a motion across its axis, lost after
# a checkpoint taken while it slides, and interrupted, then resumed: every output byte for byte
add_test(NAME cli.resume_servo_motion
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/shear/plane_shear_lid.scene
                 ${CLI_WORK}/resume_servo_motion --set stages.press.time.end=1.0
                 --set stages.shear.time.end=1.0 --set output.walls.window=[1.2,2.0]
                 --set output.checkpoint_every=0.7)
set_tests_properties(cli.resume_servo_motion PROPERTIES LABELS cli)
# a small impact (100 grains) lost after a checkpoint taken while its projectile falls, and
# interrupted, then resumed: depth.csv and summary.json's "depth" byte for byte
add_test(NAME cli.resume_impact_depth
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/impact/impact.scene ${CLI_WORK}/resume_impact_depth
                 --set grains.rain.max_count=100 --set stages.settle.time.end=1.0
                 --set stages.impact.time.end=0.8 --set sources.projectile.region=[1.49,0.9,1.51,0.91]
                 --set output.checkpoint_every=0.7)
set_tests_properties(cli.resume_impact_depth PROPERTIES LABELS cli)
# walls.png (and walls.pdf) of output.walls, its axes labelled with their units
# (tests/cli/walls_figure.sh, the figure lint tests/lint/figure_lint.py)
add_test(NAME cli.walls_figure
         COMMAND bash ${CLI_DIR}/walls_figure.sh $<TARGET_FILE:sablier> ${CLI_DIR}/servo_lid.scene
                 ${PROJECT_SOURCE_DIR}/tests/lint/figure_lint.py ${CLI_WORK}/walls_figure)
set_tests_properties(cli.walls_figure PROPERTIES LABELS cli)
# grains a stage adds: their ids, traced by name, their free fall, any thread count, and each
# refusal at its file:line (tests/cli/add_grains.sh); resumed after a checkpoint of the stage that
# added them: the same bytes (tests/cli/resume.sh --outputs)
add_test(NAME cli.add_grains
         COMMAND bash ${CLI_DIR}/add_grains.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/add_grains.scene ${CLI_WORK}/add_grains)
set_tests_properties(cli.add_grains PROPERTIES LABELS cli)
add_test(NAME cli.resume_add_grains
         COMMAND bash ${CLI_DIR}/resume.sh --outputs $<TARGET_FILE:sablier>
                 ${CLI_DIR}/add_grains.scene ${CLI_WORK}/resume_add_grains
                 --set output.checkpoint_every=0.2)
set_tests_properties(cli.resume_add_grains PROPERTIES LABELS cli)
# window that ends with its stage written at its end (tests/cli/measure_window.sh)
add_test(NAME cli.measure_window
         COMMAND bash ${CLI_DIR}/measure_window.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/measure_window.scene ${CLI_WORK}/measure_window)
set_tests_properties(cli.measure_window PROPERTIES LABELS cli)
# a stage that loads a checkpoint whose walls (or wall motions) are not the scene's: refused at
# load (tests/cli/load_walls.sh)
add_test(NAME cli.load_walls
         COMMAND bash ${CLI_DIR}/load_walls.sh $<TARGET_FILE:sablier> ${CLI_DIR}/load_walls.scene
                 ${CLI_WORK}/load_walls)
set_tests_properties(cli.load_walls PROPERTIES LABELS cli)
add_test(NAME cli.check_target_error
         COMMAND bash ${CLI_DIR}/target_error.sh $<TARGET_FILE:sablier> ${CLI_TINY})
set_tests_properties(cli.check_target_error PROPERTIES LABELS cli)

# --set paths are strict: no empty part, no unclosed or stray bracket
sablier_cli_test(set_leading_dot "check|${CLI_TINY}|--set|.time.dt=1e-5" 2
                 ERR "--set .time.dt: empty part in the key")
sablier_cli_test(set_double_dot "check|${CLI_TINY}|--set|time..dt=1e-5" 2
                 ERR "--set time..dt: empty part in the key")
# per-grain dumps (docs/dumps.md): `check` shows them, bad values are refused, the frame bound
# is lifted only by max_frames; `sablier export` usage errors
set(CLI_QUICK ${PROJECT_SOURCE_DIR}/scenes/crater/quick.scene)
sablier_cli_test(dump_check "check|${CLI_QUICK}" 0
                 OUT "stage collapse: [^\n]*\n(  [^\n]*\n)*  dump +lammps, vtk [(]\\+ contacts[)] every 0.5 s, at most 7 frames")
sablier_cli_test(dump_every_zero "check|${CLI_QUICK}|--set|stages.collapse.dump.every=0" 2
                 ERR "--set stages.collapse.dump.every: `every` must be > 0")
sablier_cli_test(dump_unknown_field "check|${CLI_QUICK}|--set|stages.collapse.dump.fields=[id,pressure]" 2
                 ERR "--set stages.collapse.dump.fields: unknown field `pressure`")
sablier_cli_test(dump_every_step_refused "check|${CLI_QUICK}|--set|stages.collapse.dump.every=5e-5" 2
                 ERR "makes up to 60001 frames, more than max_frames = 10000")
sablier_cli_test(dump_every_step_asked
                 "check|${CLI_QUICK}|--set|stages.collapse.dump.every=5e-5|--set|stages.collapse.dump.max_frames=60001"
                 0 OUT "dump +lammps, vtk [^\n]*at most 60001 frames [(]max_frames 60001[)]")
sablier_cli_test(dump_format_empty_off "check|${CLI_QUICK}|--set|stages.collapse.dump.format=[]" 0
                 OUT "stage collapse: [^\n]*\n  time step[^\n]*\n  contact time[^\n]*\n  stability limit[^\n]*\n  steps per contact[^\n]*\noutput ")
sablier_cli_test(export_no_state "export" 2 ERR "missing STATE")
sablier_cli_test(export_no_out "export|a.state" 2 ERR "missing -o FILE")
sablier_cli_test(export_bad_format "export|a.state|--format|xyz|-o|a.out" 2 ERR "unknown --format xyz")
sablier_cli_test(export_no_extension "export|a.state|-o|a.out" 2 ERR "give --format")
sablier_cli_test(export_unknown_option "export|a.state|-o|a.csv|--frob" 2 ERR "unknown option --frob")
sablier_cli_test(export_missing_state "export|no_such.state|-o|${CLI_WORK}/a.csv" 2
                 ERR "export: cannot load no_such.state")
# per-grain dumps read back by LAMMPS and VTK, export against the dump (label clients)
include(${PROJECT_SOURCE_DIR}/tests/clients/clients.cmake)
# the measures layer's .vti files read back by VTK's XML reader (docs/measures.md)
add_test(NAME cli.measures_vtk
         COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                 -DSCENE=${PROJECT_SOURCE_DIR}/scenes/measure/column.scene
                 -DWORK=${CLI_WORK}/measures_vtk -P ${CLI_DIR}/measures_vtk.cmake
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(cli.measures_vtk PROPERTIES LABELS cli SKIP_REGULAR_EXPRESSION "skipped")
# `sablier diff` on two folders: identical, changed, missing, extra, bad input, --update
# (docs/ci.md)
add_test(NAME cli.diff_folders
         COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                 -DREF=${PROJECT_SOURCE_DIR}/tests/render/reference
                 -DWORK=${CLI_WORK}/diff_folders -DRENDER=${SABLIER_WITH_RENDER}
                 -P ${CLI_DIR}/diff_folders.cmake)
set_tests_properties(cli.diff_folders PROPERTIES LABELS cli)
# the report of `sablier diff --report`: the terminal's numbers (max difference, RMS, share of
# changed pixels) in index.html and report.json, filters, blink, zoom, a PDF pair drawn as PNGs,
# relative paths, the same bytes from two runs, files written through NAME.tmp
if(SABLIER_WITH_RENDER AND SABLIER_RASTER_FOUND)
  add_test(NAME cli.diff_report
           COMMAND ${CMAKE_COMMAND} -DSABLIER=$<TARGET_FILE:sablier>
                   -DREF=${PROJECT_SOURCE_DIR}/tests/render/reference
                   -DWORK=${CLI_WORK}/diff_report -P ${CLI_DIR}/diff_report.cmake)
  set_tests_properties(cli.diff_report PROPERTIES LABELS cli)
endif()
add_test(NAME cli.render_bad_state
         COMMAND bash ${CLI_DIR}/render_bad_state.sh $<TARGET_FILE:sablier> ${CLI_TINY}
                 ${CLI_WORK}/render_bad_state)
set_tests_properties(cli.render_bad_state PROPERTIES LABELS cli)
# bad command-line values refused before anything runs or is written: an --ldf of
# inf (a heap overflow in app_bne_ldf), an orifice of width 0 ("jammed" through no orifice), an
# empty list item (was dropped), a base of 1e13 grains (exit 1, an empty message), a threshold
# above 255 (was run as 255); a --max-pixels of 2^31 - 1 is a count (was refused)
set(CLI_BNE ${PROJECT_SOURCE_DIR}/scenes/brazil_nut/small.scene)
set(CLI_DISCHARGE ${PROJECT_SOURCE_DIR}/scenes/discharge/rolling_fixed.scene)
sablier_cli_test(bne_ldf_inf "bne|${CLI_BNE}|--seeds|2|--ldf|inf|--out|${CLI_WORK}/bne_ldf_inf" 2
                 ERR "--ldf needs a number of periods in \\[0, 1e6\\] [(]0: no LDF[)], got inf")
sablier_cli_test(discharge_width_zero
                 "discharge|${CLI_DISCHARGE}|--width|0|--out|${CLI_WORK}/discharge_width_zero" 2
                 ERR "--width 0: an orifice width must be in \\[1, base_length = 25\\] d")
# a --pile that cannot be read is refused before the scene runs (exit 2, no folder half-written)
sablier_cli_test(discharge_pile_missing
                 "discharge|${CLI_DISCHARGE}|--pile|${CLI_WORK}/no_such_pile.state|--out|${CLI_WORK}/discharge_pile_missing" 2
                 ERR "--pile: cannot read .*no_such_pile.state")
sablier_cli_test(discharge_width_scene
                 "check|${CLI_DISCHARGE}|--set|discharge.widths=[2.0,0.5]" 2
                 ERR "--set discharge.widths: orifice width 0.5 d out of \\[1, base_length")
sablier_cli_test(discharge_base_too_long
                 "check|${CLI_DISCHARGE}|--set|discharge.base_length=1e12" 2
                 ERR "`base_length` 1e[+]12 d makes a base of 1e[+]13 grains")
sablier_cli_test(study_widths_empty_item
                 "study|${CLI_DISCHARGE}|--widths|1,,2|--out|${CLI_WORK}/study_widths_empty_item" 2
                 ERR "--widths must be A:B:STEP or a list, got 1,,2")
sablier_cli_test(study_widths_too_small
                 "study|${CLI_DISCHARGE}|--widths|0.5,2|--out|${CLI_WORK}/study_widths_too_small" 2
                 ERR "study: --widths 0.5: an orifice width must be in")
# sweep and study parse through the multi-run driver (app/driver/driver.h): their usage errors unchanged,
# and what one command does not take (study: --quiet, --vary) still refused
sablier_cli_test(study_no_scene "study" 2 ERR "missing SCENE\n\nusage: sablier study")
sablier_cli_test(study_quiet "study|${CLI_DISCHARGE}|--quiet" 2 ERR "unknown option --quiet")
sablier_cli_test(study_vary "study|${CLI_DISCHARGE}|--vary|seed=1,2" 2 ERR "unknown option --vary")
sablier_cli_test(study_jobs "study|${CLI_DISCHARGE}|--jobs|257" 2
                 ERR "--jobs needs a count in \\[1, 256\\], got 257")
sablier_cli_test(study_samples "study|${CLI_DISCHARGE}|--samples|0" 2
                 ERR "--samples needs a count in \\[1, 1e6\\], got 0")
sablier_cli_test(study_bad_set "study|${CLI_DISCHARGE}|--set" 2 ERR "sablier: bad --set\n\nusage")
sablier_cli_test(study_two_scenes "study|${CLI_DISCHARGE}|${CLI_DISCHARGE}" 2
                 ERR "one scene at a time; extra argument")
sablier_cli_test(sweep_no_scene "sweep" 2 ERR "missing FILE.sweep or SCENE\n\nusage: sablier sweep")
sablier_cli_test(sweep_two "sweep|a.sweep|b.sweep" 2 ERR "one sweep at a time; extra argument b.sweep")
sablier_cli_test(sweep_jobs "sweep|a.sweep|--jobs|65" 2
                 ERR "--jobs needs a count in \\[1, 64\\], got 65")
sablier_cli_test(sweep_vary_nine
                 "sweep|${CLI_QUICK}|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1|--vary|a=1"
                 2 ERR "too many --vary options")
sablier_cli_test(sweep_unknown "sweep|a.sweep|--frob" 2 ERR "unknown option --frob")
sablier_cli_test(set_array_empty_element "check|${CLI_TINY}|--set|effects=[friction,,rolling_resistance]"
                 2 ERR "--set effects: an empty element in \\[a, b, ...\\]")
sablier_cli_test(diff_threshold_over "diff|a.png|b.png|--threshold|300" 2
                 ERR "--threshold needs a count in \\[0, 255\\], got 300")
if(SABLIER_WITH_RENDER)
  set(CLI_PNG ${PROJECT_SOURCE_DIR}/tests/render/reference/annotations.png)
  sablier_cli_test(diff_max_pixels_large "diff|${CLI_PNG}|${CLI_PNG}|--max-pixels|2147483647" 0
                   OUT "\"max_pixels\": 2147483647")
endif()
# a dig beside every grain and wall is refused at load
sablier_cli_test(dig_outside "check|scenes/crater/quick.scene|--set|stages.dig.dig.center_x=1e308"
                 2 ERR "dig: the cavity .* lies outside the scene's grains and walls")
# output.energy_stage names a stage that runs for some time, else it is refused at load
sablier_cli_test(energy_stage_unknown
                 "check|scenes/crater/quick.scene|--set|output.energy_stage=\"rain\"" 2
                 ERR "output.energy_stage: `energy_stage`: no stage named `rain`")
sablier_cli_test(energy_stage_timeless
                 "check|scenes/crater/quick.scene|--set|output.energy_stage=\"dig\"" 2
                 ERR "`energy_stage`: stage `dig` runs no time")
# `sablier ensemble` (docs/accuracy.md#ensemble-accuracy): end to end on a free fall with a known
# shift (tests/cli/ensemble.sh), and its usage errors (exit 2, nothing run)
add_test(NAME cli.ensemble
         COMMAND bash ${CLI_DIR}/ensemble.sh $<TARGET_FILE:sablier> ${CLI_DIR}/ensemble_fall.scene
                 ${CLI_WORK}/ensemble ${SABLIER_WITH_RENDER})
set_tests_properties(cli.ensemble PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
# SIGINT/SIGTERM to a multi-run command stop its members through the shared pool: exit 130/143,
# no process left, the table with the unfinished members `interrupted`; --resume runs only those
# (tests/cli/pool_signal.sh)
add_test(NAME cli.pool_signal
         COMMAND bash ${CLI_DIR}/pool_signal.sh $<TARGET_FILE:sablier> ${CLI_DIR}/ensemble_fall.scene
                 ${CLI_WORK}/pool_signal)
set_tests_properties(cli.pool_signal PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
# SIGINT to `sablier bne`: samples.csv's status column says which runs were interrupted
# (tests/cli/bne_signal.sh)
add_test(NAME cli.bne_signal
         COMMAND bash ${CLI_DIR}/bne_signal.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/brazil_nut/small.scene ${CLI_WORK}/bne_signal)
set_tests_properties(cli.bne_signal PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
# the ensemble reaches the discharge protocol (its own dt: discharge.dt_divisor = 0)
add_test(NAME cli.ensemble_discharge
         COMMAND bash ${CLI_DIR}/ensemble_discharge.sh $<TARGET_FILE:sablier>
                 ${PROJECT_SOURCE_DIR}/scenes/discharge/rolling_fixed.scene
                 ${CLI_WORK}/ensemble_discharge)
set_tests_properties(cli.ensemble_discharge PROPERTIES LABELS cli
                     ENVIRONMENT "LSAN_OPTIONS=suppressions=${CLI_DIR}/lsan.supp")
set(CLI_FALL ${CLI_DIR}/ensemble_fall.scene)
sablier_cli_test(help_ensemble "ensemble|--help" 0 OUT "usage: sablier ensemble")
sablier_cli_test(ensemble_no_scene "ensemble|--dt|1e-3,2e-3|--observe|seed" 2 ERR "missing SCENE")
sablier_cli_test(ensemble_no_dt "ensemble|${CLI_FALL}|--observe|seed" 2
                 ERR "missing --dt LIST or --steps-per-contact LIST")
sablier_cli_test(ensemble_no_observe "ensemble|${CLI_FALL}|--dt|1e-3,2e-3" 2
                 ERR "missing --observe KEY")
sablier_cli_test(ensemble_one_dt "ensemble|${CLI_FALL}|--dt|1e-3|--observe|seed" 2
                 ERR "at least two values")
sablier_cli_test(ensemble_bad_dt "ensemble|${CLI_FALL}|--dt|1e-3,fast|--observe|seed" 2
                 ERR "bad list .* after --dt")
sablier_cli_test(ensemble_zero_dt "ensemble|${CLI_FALL}|--dt|1e-3,0|--observe|seed" 2
                 ERR "every value must be > 0")
sablier_cli_test(ensemble_same_dt "ensemble|${CLI_FALL}|--dt|1e-3,0.001|--observe|seed" 2
                 ERR "a value given twice")
sablier_cli_test(ensemble_two_lists
                 "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--steps-per-contact|50,100|--observe|seed" 2
                 ERR "give one list")
sablier_cli_test(ensemble_one_seed "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--seeds|1|--observe|seed"
                 2 ERR "--seeds needs a count in \\[2, 10000\\]")
sablier_cli_test(ensemble_bad_key "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--observe|../x.json:a" 2
                 ERR "--observe: `../x.json:a`: the file must be")
sablier_cli_test(ensemble_key_twice "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--observe|seed,seed" 2
                 ERR "key given twice")
sablier_cli_test(ensemble_unknown_option
                 "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--observe|seed|--command|run" 2
                 ERR "unknown option --command")
sablier_cli_test(ensemble_bad_set
                 "ensemble|${CLI_FALL}|--dt|1e-3,2e-3|--observe|seed|--set|nope.key=1" 2
                 ERR "--set nope.key: unknown key `nope`")
sablier_cli_test(ensemble_capped_steps
                 "ensemble|${PROJECT_SOURCE_DIR}/scenes/crater/small.scene|--steps-per-contact|12,25|--observe|seed|--set|time.max_dt_fraction=0"
                 2 ERR "--steps-per-contact 12 and 25 give the same time step")
sablier_cli_test(ensemble_stage_dt
                 "ensemble|${PROJECT_SOURCE_DIR}/scenes/crater/small.scene|--dt|2e-5,4e-5|--observe|crater.crater_height|--set|stages.collapse.time.dt=1e-5"
                 2 ERR "stage `collapse` sets its own time.dt")
# hard cases of the drum, source, intruder, shear and chute features at the CLI
# (docs/physics.md#hard-cases; the sim-level ones are tests/stability/test_hard_cases.c)
foreach(mode insert_dense chute_unbounded resume_threads)
  add_test(NAME cli.hard.${mode}
           COMMAND bash ${CLI_DIR}/hard_cases.sh $<TARGET_FILE:sablier> ${mode} ${CLI_DIR}
                   ${CLI_WORK}/hard_${mode})
  set_tests_properties(cli.hard.${mode} PROPERTIES LABELS cli)
endforeach()
# a drum turning so fast that one step no longer resolves its wall's speed: refused at load
sablier_cli_test(hard.drum_too_fast
                 "check|${PROJECT_SOURCE_DIR}/scenes/drum/drum.scene|--set|motions.spin.angular_velocity=10"
                 2 ERR "motion 0 moves its walls or fixed grains at up to [0-9.]+ m/s.*wall-speed limit")
# the shipped chute made frictionless and tilted to 60 degrees (rough base): it accelerates
# without bound (E_kin ~ t^2) until the automatic guard stops it near t = 290 s, exit 1, the
# cause named, the message whole (not cut at sim's 400 characters); ~12 s, label slow
sablier_cli_test(hard.chute_rough_unbounded
                 "run|${PROJECT_SOURCE_DIR}/scenes/chute/chute.scene|--quiet|--out|${CLI_WORK}/hard_chute_rough|--set|species.0.mu=0|--set|species.1.mu=0|--set|stages.flow.gravity=[0.8660254,-0.5]|--set|stages.flow.time.end=400"
                 1 ERR "stage flow: simulation failed at step [0-9]+ [(]t = [0-9.]+ s[)].*the flow accelerates without bound.*or stop earlier [(]dt = ")
set_tests_properties(cli.hard.chute_rough_unbounded PROPERTIES LABELS "cli;slow")
# insertion sources: the same bytes on 1, 2, 3 and 8 threads, the automatic time step
# of a scene fed by sources alone, a rate bounded by what the region holds per step, and the
# insertion stopped by a signal
foreach(mode threads auto_dt rate_bound interrupt)
  add_test(NAME cli.sources.${mode}
           COMMAND bash ${CLI_DIR}/sources.sh $<TARGET_FILE:sablier> ${mode} ${CLI_DIR}
                   ${PROJECT_SOURCE_DIR} ${CLI_WORK}/sources_${mode})
  set_tests_properties(cli.sources.${mode} PROPERTIES LABELS cli)
endforeach()
# sablier check prints a scene's own units (docs/scenes.md#units): d and sqrt(d/g), not m and s
sablier_cli_test(check_normalised_units "check|scenes/measure/column.scene" 0
                 OUT "gravity \\(0, -1\\) g\n.*time.end 4 sqrt\\(d/g\\), measure stress \\(profile_y, 1 x 80 nodes, width 2 d, every 0.1 sqrt\\(d/g\\)\\)")
# protocols that chain (docs/scenes.md, stages): a motion keeps its clock across stages and
# `restart_motions` restarts it (tests/cli/motion_clock.sh); a settle test over a window of time
# (tests/cli/settle_window.sh)
add_test(NAME cli.motion_clock
         COMMAND bash ${CLI_DIR}/motion_clock.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/motion_clock.scene ${CLI_WORK}/motion_clock)
add_test(NAME cli.settle_window
         COMMAND bash ${CLI_DIR}/settle_window.sh $<TARGET_FILE:sablier>
                 ${CLI_DIR}/settle_window.scene ${CLI_WORK}/settle_window)
set_tests_properties(cli.motion_clock cli.settle_window PROPERTIES LABELS cli)
# `check` warns about motions that move nothing, with their lines, and still exits 0
set(MOTION_WARN ${CLI_DIR}/motion_warn.scene)
sablier_cli_test(motion_warn_unused "check|${MOTION_WARN}" 0
                 ERR "motion_warn.scene:16: warning: motion `spare` moves nothing")
sablier_cli_test(motion_warn_part "check|${MOTION_WARN}" 0
                 ERR "motion_warn.scene:24: warning: stage `shear` enables motion `shear`, which moves nothing: what it moves follows motion `both`")
sablier_cli_test(motion_warn_none "check|${CLI_DIR}/motion_clock.scene" 0 NOT_ERR "warning")
# `check` names the tangential law and whether it has static friction
sablier_cli_test(friction_regularised "check|${PROJECT_SOURCE_DIR}/scenes/validation/oblique_drop.scene" 0
                 OUT "friction regularised Coulomb[^\n]*no static friction")
sablier_cli_test(friction_spring "check|${PROJECT_SOURCE_DIR}/scenes/hopper/hopper.scene" 0
                 OUT "friction spring [^\n]*static friction")
# --unset KEY: removes a key (and a law's dependents), in order with --set; run and check
set(HOPPER ${PROJECT_SOURCE_DIR}/scenes/hopper/hopper.scene)
sablier_cli_test(unset_law_dependents
                 "check|${HOPPER}|--unset|contact.tangential|--set|species.0.gamma_s=5" 0
                 OUT "friction regularised")
sablier_cli_test(unset_then_set_law
                 "check|${HOPPER}|--unset|species.0.k_t|--set|contact.tangential=regularised|--set|species.0.gamma_s=5"
                 0 OUT "friction regularised")
sablier_cli_test(unset_needed "check|${HOPPER}|--set|contact.tangential=regularised|--set|species.0.gamma_s=5"
                 2 ERR "hopper.scene:12: `k_t` is used only by contact.tangential = \"spring\"")
sablier_cli_test(unset_required_key "check|${HOPPER}|--unset|species.0.k_t" 2
                 ERR "hopper.scene:12: missing required key `k_t` in species 0")
sablier_cli_test(unset_unknown "check|${CLI_TINY}|--unset|nope.key" 2
                 ERR "--unset nope.key: no such key in the scene")
sablier_cli_test(unset_unknown_run "run|${CLI_TINY}|--unset|species.0.mu" 2
                 ERR "--unset species.0.mu: no such key in the scene")
sablier_cli_test(unset_with_value "check|${CLI_TINY}|--unset|time.dt=1" 2
                 ERR "--unset time.dt=1: expected a KEY alone")
sablier_cli_test(unset_group "check|${CLI_TINY}|--unset|output" 0 OUT "energy every")
