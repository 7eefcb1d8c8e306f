#!/usr/bin/env bash
# CPU time per iteration of each step method, against plain (the
# per-iteration overhead). For each method it runs
#   masssprings simulate SCENE --steps S --iterations N --method M
# at N = 50 and N = 250, takes the difference of the CPU times (user + sys,
# so that another process on the machine slows the figure less than wall
# time would) to remove the precomputation, and divides by S × 200. The
# minimum of R interleaved rounds is printed, with the ratio to plain.
#
# usage: benches/iteration_cost.sh SCENE.json [STEPS] [ROUNDS] [METHODS]
#   e.g. benches/iteration_cost.sh data/skirt.json 3 5 plain,chebyshev,anderson,lbfgs
set -euo pipefail
scene=${1:?usage: benches/iteration_cost.sh SCENE.json [STEPS] [ROUNDS] [METHODS]}
steps=${2:-5}
rounds=${3:-5}
methods=${4:-plain,chebyshev,anderson,lbfgs}
bin=target/release/masssprings
cargo build --release --quiet
cpu_seconds() { # CPU seconds of one run
  local TIMEFORMAT='%U %S'
  { time "$bin" simulate "$scene" --steps "$steps" --iterations "$1" --method "$2" --json > /dev/null 2>&1; } 2>&1 |
    awk '{ print $1 + $2 }'
}
declare -A low high
for _ in $(seq "$rounds"); do
  for method in ${methods//,/ }; do
    for n in 50 250; do
      t=$(cpu_seconds "$n" "$method")
      if [ "$n" = 50 ]; then
        low[$method]=$(awk -v a="${low[$method]:-1e9}" -v b="$t" 'BEGIN { print (b < a) ? b : a }')
      else
        high[$method]=$(awk -v a="${high[$method]:-1e9}" -v b="$t" 'BEGIN { print (b < a) ? b : a }')
      fi
    done
  done
done
base=""
for method in ${methods//,/ }; do
  per=$(awk -v h="${high[$method]}" -v l="${low[$method]}" -v s="$steps" 'BEGIN { print 1000 * (h - l) / (s * 200) }')
  base=${base:-$per}
  awk -v m="$method" -v p="$per" -v b="$base" 'BEGIN { printf "%s %.4f ms (%.3fx)  ", m, p, p / b }'
done
echo
