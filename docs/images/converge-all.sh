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
