# shellcheck shell=bash
# SPDX-License-Identifier: MIT
# The shipped scenes under the figure lint (sourced by tests/lint/figures.sh scenes; ctest
# lint.figures.scene.GROUP, docs/figures.md#figure-lint). scene_GROUP runs the group's scenes
# from the repository root into $work/NAME with `$sablier`, every plot and grain figure also as
# PDF (render.plot_format = "pdf"), cut short with --set (stage ends, grain counts, one orifice
# width, one or two seeds) so that a group takes seconds, and checks that each figure and plot
# the scenes declare was written (a shortened run must still draw every kind).
# Not here: scenes/measure/column.scene (lint.figures runs it with the gallery) and
# scenes/validation/ (energy.csv and trace.csv only: no figure, no plot).
# To add a scene: a `run` and an `expect` line in its group's function (or a new scene_GROUP
# and its name in tests/CMakeLists.txt's list).

# from figures.sh: $sablier (an absolute path) and $work (the group's empty output folder)
: "${sablier:?}" "${work:?}"
pdf=(--quiet --set 'render.plot_format="pdf"')

# run NAME COMMAND SCENE ARGS...: `sablier COMMAND scenes/SCENE` into $work/NAME (log NAME.log)
run() {
  local name=$1 command=$2 scene=$3
  shift 3
  "$sablier" "$command" "scenes/$scene" --out "$work/$name" "${pdf[@]}" "$@" \
    >"$work/$name.log" 2>&1 || { cat "$work/$name.log" >&2; return 1; }
}

# expect NAME FILE...: the run NAME wrote every FILE
expect() {
  local name=$1 file
  shift
  for file in "$@"; do
    [ -e "$work/$name/$file" ] || { echo "figure_scenes.sh: $name wrote no $file" >&2; return 1; }
  done
}

scene_chute() {
  run chute run chute/chute.scene --set stages.settle.time.end=5 --set stages.flow.time.end=3 \
    --set stages.flow.measures.0.window=2 --set 'output.movie=[]' &&
    expect chute chute.pdf velocity_vx.pdf
}

scene_drum() {
  run drum run drum/drum.scene --set stages.settle.time.end=3 --set stages.rotate.time.end=4 \
    --set surface.after=1 --set 'output.movie=[]' && expect drum drum.pdf
}

scene_hopper() {
  run hopper run hopper/hopper.scene --set stages.fill.time.end=4 --set 'output.movie=[]' &&
    expect hopper hopper.pdf
}

scene_compression() {
  run biaxial run compression/biaxial.scene --set stages.pack.time.end=1 \
    --set stages.compress.time.end=2 --set 'output.walls.window=[1.0,3.0]' &&
    expect biaxial biaxial.pdf walls.pdf
}

scene_shear() {
  run plane_shear run shear/plane_shear.scene --set stages.press.time.end=0.5 \
    --set stages.shear.time.end=0.5 --set 'output.walls.window=[0.5,1.0]' &&
    expect plane_shear plane_shear.pdf walls.pdf &&
    run couette run shear/couette.scene --set stages.settle.time.end=2 \
      --set stages.shear.time.end=2 --set 'output.movie=[]' &&
    expect couette couette.pdf
}

scene_silo() {
  run janssen run silo/janssen.scene --set stages.fill.time.end=1 \
    --set 'output.walls.window=[0.5,1.0]' && expect janssen janssen.pdf walls.pdf
}

scene_impact() {
  run impact run impact/impact.scene --set stages.settle.time.end=0.5 \
    --set stages.impact.time.end=0.3 && expect impact impact.pdf
}

# the pile (L = 10 d) and one orifice: pile.png and w<W>.png, the arch in its inset; a short
# study's plots
scene_discharge() {
  local s w
  for s in bidisperse:3.0 density:3.0 poly:2.2 rolling_chord:2.2 rolling_fixed:2.2; do
    w=${s#*:} s=${s%:*}
    run "$s" discharge "discharge/$s.scene" --width "$w" --figures \
      --set discharge.base_length=10 && expect "$s" pile.pdf "w$w.pdf" || return 1
  done
  # the study's reduction plots (`sablier study` takes no --quiet)
  "$sablier" study scenes/discharge/bidisperse.scene --out "$work/study" --L 10,12 \
    --widths 1.5,2.5 --samples 2 --set 'render.plot_format="pdf"' >"$work/study.log" 2>&1 ||
    { cat "$work/study.log" >&2; return 1; }
  expect study h_mean.pdf sigma_h.pdf wt.pdf composition.pdf
}

# the large boxes' own figures (bands, the velocity field, the phase field) from `sablier run`
scene_brazil_nut() {
  local s cut=(--set stages.settle.time.end=3 --set stages.settle.settle.after=1
    --set stages.shake.time.end=4 --set 'output.movie=[]' --set grains.rain.max_count=600)
  for s in box smooth_walls; do
    run "$s" run "brazil_nut/$s.scene" "${cut[@]}" --set bne.phase_field.skip_cycles=0 &&
      expect "$s" bands_start.pdf bands_end.pdf flow_end.pdf phase_field.pdf || return 1
  done
  for s in frictionless periodic; do
    run "$s" run "brazil_nut/$s.scene" "${cut[@]}" &&
      expect "$s" bands_start.pdf bands_end.pdf || return 1
  done
}

# the small boxes through `sablier bne`: rise curves and the large-deviation function
scene_brazil_nut_bne() {
  local s
  for s in small small_density small_frictionless; do
    run "$s" bne "brazil_nut/$s.scene" --seeds 2 --ldf 1 --set stages.settle.time.end=4 \
      --set stages.settle.settle.after=2 --set stages.shake.time.end=10 &&
      expect "$s" rise.pdf ldf.pdf || return 1
  done
}

# the bed with its profile panels (run; also in SI, whose panels say m and m/s) and the Shields
# scan's flux plot (sablier sediment)
scene_sediment() {
  local cut=(--set stages.settle.time.end=2 --set stages.flow.time.end=2)
  run viscous run sediment/viscous.scene "${cut[@]}" --set 'output.movie=[]' &&
    expect viscous bed.pdf &&
    run viscous_si run sediment/viscous.scene "${cut[@]}" --set 'output.movie=[]' \
      --set 'units="SI"' && expect viscous_si bed.pdf &&
    run shields sediment sediment/viscous.scene --shields 0.4,0.8 "${cut[@]}" &&
    expect shields flux.pdf
}

scene_crater() {
  local fig=(settled.pdf cavity.pdf crater.pdf collapse_0.2s.pdf collapse_0.5s.pdf
    collapse_1.0s.pdf velocity_0.2s.pdf velocity_0.5s.pdf energy_panels.pdf profiles.pdf)
  run quick run crater/quick.scene --set grains.rain.max_count=300 \
    --set stages.deposit.time.end=0.5 --set stages.collapse.time.end=1.0 \
    --set 'output.movie=[]' --set 'stages.collapse.dump.format=[]' && expect quick "${fig[@]}" &&
    run standard run crater/standard.scene --set time.dt=5e-5 --set grains.rain.max_count=300 \
      --set stages.deposit.time.end=0.5 --set stages.collapse.time.end=1.0 \
      --set 'output.movie=[]' --set stages.dig.dig.width=2.1 && expect standard "${fig[@]}" &&
    run small run crater/small.scene --set grains.rain.max_count=150 \
      --set stages.deposit.time.end=0.5 --set stages.deposit.settle.after=0.2 \
      --set stages.collapse.time.end=0.3 --set stages.collapse.settle.after=0.1 &&
    expect small settled.pdf crater.pdf energy_panels.pdf profiles.pdf
}

# every sweep's comparison plots (the members' own figures are the scene's: scene_crater)
scene_crater_sweeps() {
  local s dt
  for s in alpha aspect gamma_n gamma_s kn mu quick-tuned tuned; do
    dt=5e-5
    [ $s != kn ] || dt=2.5e-5 # the stiffest member's contact time allows no more
    run "$s" sweep "crater/sweeps/$s.sweep" --set time.dt=$dt --set grains.rain.max_count=150 \
      --set stages.deposit.time.end=0.3 --set stages.collapse.time.end=0.2 \
      --set 'output.movie=[]' --unset output.figures &&
      expect "$s" energy_panels.pdf crater_height.pdf profiles.pdf || return 1
  done
}
