#!/usr/bin/env bash
# Redraws the pictures of docs/mistakes.md: each of the usual mistakes
# (masssprings::sim::mistakes) drawn beside the handout's step, on the scene
# that shows it best, 480×180 (two panels of 240×180). The flag's fall is
# over in a few frames, so it is drawn every 2nd step for 2 s; the chain and
# the single spring swing for longer, every 3rd step for 3 s. Each GIF stays
# under 300 KB.
#
#     bash docs/images/mistakes.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
source docs/images/program.sh
mkdir -p docs/images/mistakes

draw() {
    local scene=$1 mistake=$2 steps every
    if [ "$scene" = flag ]; then steps=60 every=2; else steps=90 every=3; fi
    "$MASSSPRINGS" render "data/$scene.json" --mistake "$mistake" \
        --steps "$steps" --every "$every" --size 480x180 \
        -o "docs/images/mistakes/$mistake.gif"
}

draw horizontal-chain mass-doubled
draw flag a-sign
draw flag pins-not-in-q
draw flag pins-not-in-b
draw flag r-from-deformed
draw horizontal-chain dt-not-squared
draw single-spring-horizontal prev-cur-swapped
draw flag d-not-normalised
draw single-spring-horizontal pins-one-based
draw flag gravity-times-mass
draw single-spring-horizontal d-from-u-cur
draw single-spring-horizontal inertia-minus-prev
draw flag inertia-sign
draw horizontal-chain inertia-half-missing
