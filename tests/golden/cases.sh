# SPDX-License-Identifier: MIT
# The golden cases (tests/golden/README.md): one short run of every experiment family.
# Sourced by check.sh and record.sh; run from the repository root.
#   golden_cases             prints the case names
#   golden_run CASE BIN OUT  runs CASE with the binary BIN into the (absolute, fresh) folder OUT
# GOLDEN_THREADS (environment, empty by default): more arguments for the cases that are one
# `sablier run` (crater, brazil_nut, sediment), such as `--threads 3`: the outputs must be the
# recorded ones on any thread count (check_threads.sh).
read -r -a golden_threads <<<"${GOLDEN_THREADS:-}"
golden_cases() {
  echo crater brazil_nut sediment discharge sweep bne_samples study sediment_shields
}

golden_run() {
  local case=$1 bin=$2 out=$3
  case $case in
    crater) # deposit -> dig -> collapse; the final crater figure with velocity arrows
      "$bin" run scenes/crater/small.scene --out "$out" --quiet ${golden_threads[@]+"${golden_threads[@]}"} \
        --set stages.collapse.time.end=1.0 \
        --set render.width=300 --set render.height=300 \
        --set output.figures.1.velocity_arrows=true ;;
    brazil_nut) # settle, 100 s of shaking (the intruder rises), phase-averaged field (4 phases)
      "$bin" run scenes/brazil_nut/small.scene --out "$out" --quiet ${golden_threads[@]+"${golden_threads[@]}"} \
        --set stages.shake.time.end=100 --set bne.phase_field.phases=4 \
        --set render.width=200 --set render.height=400 ;;
    sediment) # settle dry, 10 time units of flow; no movie
      "$bin" run scenes/sediment/viscous.scene --out "$out" --quiet ${golden_threads[@]+"${golden_threads[@]}"} \
        --set 'output.movie=[]' --set stages.flow.time.end=10 \
        --set output.figures.0.width=600 --set output.figures.0.height=250 ;;
    discharge) # one pile on L = 10 d, a jamming width and a catastrophic one
      "$bin" discharge scenes/discharge/rolling_fixed.scene --out "$out" --quiet \
        --set discharge.base_length=10 --width 2.2 --width 4.2 --figures \
        --set render.width=480 --set render.height=270 ;;
    sweep) # the bed once, two members (mu) from it, comparison figures
      "$bin" sweep scenes/crater/small.scene --out "$out" --quiet --jobs 2 \
        --vary species.0.mu=0.3,0.8 --set stages.collapse.time.end=1.0 \
        --set render.width=300 --set render.height=300 ;;
    bne_samples) # sablier bne: 2 seeds x 2 Gammas, rise curves and the LDF
      "$bin" bne scenes/brazil_nut/small.scene --out "$out" --quiet \
        --seeds 2 --vary bne.gamma=2,3 --ldf 3 \
        --set stages.shake.time.end=60 --set bne.phase_field.phases=2 ;;
    study) # sablier study: two species, L = 10 and 12 d, 2 samples, 3 widths, fits and maps
      "$bin" study scenes/discharge/bidisperse.scene --out "$out" \
        --L 10,12 --widths 1.5,2.5,4.0 --samples 2 --jobs 2 \
        --set render.width=480 --set render.height=270 ;;
    sediment_shields) # sablier sediment: Shields scan over two numbers, threshold estimate
      "$bin" sediment scenes/sediment/viscous.scene --out "$out" --quiet \
        --shields 0.1,0.8 --jobs 2 --set stages.flow.time.end=10 ;;
    *) echo "golden: unknown case \`$case\`" >&2; return 2 ;;
  esac
}
