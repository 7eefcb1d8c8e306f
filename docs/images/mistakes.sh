#!/usr/bin/env bash
# Redraws the pictures of docs/mistakes.md: each mistake of the gallery
# (masssprings::sim::mistakes::gallery) drawn beside the handout's step, from
# rest, on the scene its row of the table "Every mistake" names (the table is
# the gallery's entries, held to them by tests/sim/mistakes.rs), 480×180 (two
# panels of 240×180). The flag's fall is over in a few frames, so it is drawn
# every 2nd step for 2 s; the other scenes swing for longer, every 3rd step for
# 3 s. Each GIF stays under 300 KB. Prints each run's figures as JSON (the
# numbers the gallery quotes: render --mistake NAME --json).
#
#     bash docs/images/mistakes.sh            # every picture
#     bash docs/images/mistakes.sh NAME...    # only these, e.g. a new mistake's
set -euo pipefail
cd "$(dirname "$0")/../.."
source docs/images/program.sh
mkdir -p docs/images/mistakes

# The rows of the table "Every mistake": | [`NAME`](#NAME) | line | `SCENE` | …
table=$(sed -n '/^## Every mistake/,/^## [^E]/p' docs/mistakes.md | grep '^| \[`')

scene_of() {
    echo "$table" | grep "^| \[\`$1\`\]" | awk -F'|' '{ print $4 }' | tr -d ' `'
}

draw() {
    local mistake=$1 scene steps every
    scene=$(scene_of "$mistake")
    if [ -z "$scene" ]; then
        echo "$mistake: no row in the table of docs/mistakes.md (add it first)" >&2
        exit 1
    fi
    if [ "$scene" = flag ]; then steps=60 every=2; else steps=90 every=3; fi
    "$MASSSPRINGS" render "data/$scene.json" --mistake "$mistake" \
        --steps "$steps" --every "$every" --size 480x180 --json \
        -o "docs/images/mistakes/$mistake.gif"
}

if [ $# -eq 0 ]; then
    set -- $(echo "$table" | sed 's/^| \[`\([^`]*\)`.*/\1/')
fi
for mistake in "$@"; do
    draw "$mistake"
done
