#!/usr/bin/env bash
# Redraws the convergence plots of docs/convergence.md (and prints the
# tables the chapter quotes). Run from the repository root.
set -euo pipefail
bin=target/release/masssprings
cargo build --release --quiet
tmp=$(mktemp -d)
"$bin" generate grid 32 --out "$tmp" > /dev/null
for scene in data/flag.json data/skirt.json "$tmp/grid-32.json"; do
  name=$(basename "$scene" .json)
  for step in 1 11; do
    "$bin" converge "$scene" --step "$step" --plot "docs/images/converge-$name-$step.png"
  done
done
rm -r "$tmp"
# Steps 1-30 solved by the floor and the energy rule, each against plain-50
# (docs/convergence.md, "When to stop").
for name in flag skirt; do
  "$bin" converge "data/$name.json" --steps 30 --energy-tolerance 0.15 --at-least-plain 50 \
    --methods chebyshev,anderson,lbfgs --iterations 50 --plot "docs/images/steps-$name-floor.png"
done
# What --accuracy assignment spends against an oracle that knows plain-50's
# energy, and how much the flag moves by plain-50, the accuracy and
# converged steps (docs/convergence.md, "How to choose"). They time steps:
# run on a quiet machine.
for name in flag skirt; do
  "$bin" converge "data/$name.json" --steps 100 --accuracy assignment \
    --oracle "docs/images/oracle-$name.png"
  rm "docs/images/oracle-$name.csv"
done
"$bin" converge data/flag.json --steps 300 --accuracy assignment --motion docs/images/motion-flag.png
