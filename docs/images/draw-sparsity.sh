#!/usr/bin/env bash
# Redraws the sparsity pictures of docs/sparse-cholesky.md and docs/README.md:
# the flag's Q and its Cholesky factor L in the natural and the AMD order
# (masssprings spy), and the elimination tree with its supernodes of the
# 8 × 8 grid cloth (masssprings etree). Every picture is drawn by the project.
#
#     bash docs/images/draw-sparsity.sh
#
# The program: docs/images/program.sh (the test profile's binary unless
# MASSSPRINGS names another).
set -euo pipefail
cd "$(dirname "$0")/../.."
source docs/images/program.sh
grid=$(mktemp -d)
trap 'rm -rf "$grid"' EXIT

for ordering in natural amd; do
    "$MASSSPRINGS" spy data/flag.json --ordering "$ordering" --size 360 \
        -o "docs/images/flag-q-$ordering.png"
    "$MASSSPRINGS" spy data/flag.json --ordering "$ordering" --size 360 --factor \
        -o "docs/images/flag-l-$ordering.png"
done
"$MASSSPRINGS" generate grid 8 --out "$grid" > /dev/null
"$MASSSPRINGS" etree "$grid/grid-8.json" --size 720x300 -o docs/images/grid-8-etree.png
"$MASSSPRINGS" spy "$grid/grid-8.json" --factor --size 256 -o docs/images/grid-8-l-amd.png
