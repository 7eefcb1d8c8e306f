#!/usr/bin/env bash
# `--accuracy assignment` against the assignment's 50 plain iterations on
# every bundled scene and benchmark grid, as bundled, with the spring
# constant k ×0.1 and ×10, and with Δt halved and doubled: the table of
# docs/convergence.md, section 6. Each cell is what a user gets, the two
# runs each on its own from rest:
#   median step time over plain-50's median / total over plain-50's total,
#   steps above plain-50's energy along its own trajectory
# from `masssprings converge SCENE --steps S --accuracy assignment
# [--delta-t DT]`, and after them, in brackets, the median step ratio with
# every step of both solved from plain-50's state. The scenes with k scaled
# are copies of the generated ones with "k" rewritten. It measures time:
# run it on a quiet machine.
#
# usage: benches/accuracy_matrix.sh [STEPS] [SCENES]
#   e.g. benches/accuracy_matrix.sh 100 "flag net grid-32"
# SCENES are names of `masssprings generate examples` or grid-N (default:
# single-spring-horizontal horizontal-chain net flag skirt grid-16 grid-32
# grid-64). The skirt's variants take long; it is run as bundled only.
set -euo pipefail
steps=${1:-100}
scenes=${2:-"single-spring-horizontal horizontal-chain net flag skirt grid-16 grid-32 grid-64"}
bin=$PWD/target/release/masssprings
cargo build --release --quiet
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" generate -o "$work" examples >/dev/null
for s in $scenes; do
  case $s in grid-*) "$bin" generate -o "$work" grid "${s#grid-}" >/dev/null ;; esac
  for f in 0.1 10; do
    python3 - "$work/$s.json" "$work/$s-k$f.json" "$f" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["k"] = scene["k"] * float(sys.argv[3])
json.dump(scene, open(sys.argv[2], "w"))
PY
  done
done
cell() { # SCENE.json [--delta-t DT]: "median/total, above (same-states median)"
  local out own along same
  out=$("$bin" converge "$@" --steps "$steps" --accuracy assignment 2>/dev/null)
  own=$(grep 'each on its own' <<<"$out")
  along=$(grep 'along its own trajectory' <<<"$out")
  same=$(grep 'from the same states' <<<"$out")
  printf '%.2f/%.2f, %s (%.2f)' \
    "$(grep -o 'median step ratio [0-9.]*' <<<"$own" | tr -dc '0-9.')" \
    "$(grep -o 'ratio [0-9.]*,' <<<"$own" | head -1 | tr -dc '0-9.')" \
    "$(grep -o 'states: [0-9]* of' <<<"$along" | tr -dc '0-9')" \
    "$(grep -o 'median step ratio [0-9.]*' <<<"$same" | tr -dc '0-9.')"
}
echo "| scene | as bundled | k ×0.1 | k ×10 | Δt ÷2 | Δt ×2 |"
echo "|---|---|---|---|---|---|"
for s in $scenes; do
  row="| $s | $(cell "$work/$s.json")"
  if [ "$s" != skirt ]; then
    row="$row | $(cell "$work/$s-k0.1.json") | $(cell "$work/$s-k10.json")"
    row="$row | $(cell "$work/$s.json" --delta-t 0.0166666666666667)"
    row="$row | $(cell "$work/$s.json" --delta-t 0.0666666666666667)"
  fi
  echo "$row |"
done
