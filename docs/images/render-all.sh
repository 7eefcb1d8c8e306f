#!/usr/bin/env bash
# Regenerates the GIFs of docs/gallery.md: every bundled scene of data/,
# simulated for 150 steps (5 s) and drawn every 2nd step at 360×270, so each
# plays in real time at 15 frames per second and stays well under 1.5 MB.
#
#     bash docs/images/render-all.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
source docs/images/program.sh

render() {
    local scene=$1
    shift
    "$MASSSPRINGS" render "data/$scene.json" \
        --steps 150 --every 2 --size 360x270 "$@" -o "docs/images/$scene.gif"
}

render single-spring-horizontal
render horizontal-chain
render net
render flag --wind
render skirt
