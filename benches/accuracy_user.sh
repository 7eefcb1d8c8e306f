#!/usr/bin/env bash
# What a user gets from --accuracy assignment: `masssprings simulate SCENE
# --steps S --json` with and without the flag, each run on its own from
# rest, in interleaved rounds; prints per round the median step time with
# the flag over the median without it (and the iterations its steps took).
# It measures time: run it on a quiet machine.
#
# usage: benches/accuracy_user.sh [ROUNDS] [STEPS] [SCENE.json ...]
#   e.g. benches/accuracy_user.sh 5 100 data/flag.json data/skirt.json
set -euo pipefail
rounds=${1:-5}
steps=${2:-100}
shift $(( $# < 2 ? $# : 2 ))
scenes=("${@:-data/flag.json}")
[ $# -eq 0 ] && scenes=(data/flag.json data/skirt.json)
bin=$PWD/target/release/masssprings
cargo build --release --quiet
median_step() { # ARGS...: the run's median step time in seconds, and its median iterations
  "$bin" simulate "$@" --steps "$steps" --json 2>/dev/null |
    python3 -c 'import json, sys; d = json.load(sys.stdin); print(d["step_median_s"], d["iterations_median"])'
}
for scene in "${scenes[@]}"; do
  ratios=()
  for _ in $(seq "$rounds"); do
    read -r fast iterations < <(median_step "$scene" --accuracy assignment)
    read -r plain _ < <(median_step "$scene")
    ratios+=("$(python3 -c "print(f'{$fast / $plain:.3f}')")")
  done
  echo "$scene: median step with --accuracy assignment over without, per round: ${ratios[*]} (median $iterations iterations a step)"
done
