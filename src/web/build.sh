#!/usr/bin/env bash
# Builds the page that runs masssprings in a browser, with nothing to
# install: a static folder that any static host serves as it is.
#
#   bash src/web/build.sh [FOLDER]         # default: target/web
#   python3 -m http.server -d target/web 8000
#
# FOLDER gets the viewer's page (src/app/view/assets: index.html, its
# script, style and plot) with the backend that runs the simulation in the
# page (src/web/backend.js, in place of the HTTP one, and the worker
# host.mjs), the WebAssembly module (masssprings.wasm: the library and
# src/web/lib.rs, built for wasm32-unknown-unknown with the `wasm` profile)
# and its script (masssprings.mjs), and the bundled scenes of data/ with
# their textures (scenes/, listed in scenes/index.json). The folder is made
# anew; it is never committed. Needs the Rust target:
# `rustup target add wasm32-unknown-unknown`.
set -euo pipefail
web="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$web/../.." && pwd)"
out="${1:-$root/target/web}"

if command -v rustup >/dev/null 2>&1 &&
  ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  echo "build.sh: the Rust target wasm32-unknown-unknown is missing:" \
    "rustup target add wasm32-unknown-unknown" >&2
  exit 1
fi
# A warning in the library or the module fails the build (the
# dependencies' are capped by cargo, as always).
CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUSTFLAGS="-D warnings" \
  cargo build --manifest-path "$root/Cargo.toml" -p masssprings-web \
  --target wasm32-unknown-unknown --profile wasm
wasm="$root/target/wasm32-unknown-unknown/wasm/masssprings_web.wasm"

rm -rf "$out"
mkdir -p "$out/scenes"
cp "$wasm" "$out/masssprings.wasm"
cp "$web/masssprings.mjs" "$web/host.mjs" "$web/backend.js" "$out/"
page="$root/src/app/view/assets"
cp "$page/viewer.html" "$out/index.html"
cp "$page/viewer.js" "$page/plot.js" "$page/viewer.css" "$out/"

# The bundled scenes, each its JSON and the files it names (the page reads
# the names from the JSON, as the command line does).
scenes=(flag skirt horizontal-chain net single-spring-horizontal)
for scene in "${scenes[@]}"; do
  cp "$root/data/$scene.json" "$root/data/$scene.obj" "$out/scenes/"
done
cp "$root"/data/*.png "$out/scenes/"
{
  printf '['
  separator=''
  for scene in "${scenes[@]}"; do
    printf '%s"%s"' "$separator" "$scene"
    separator=', '
  done
  printf ']\n'
} >"$out/scenes/index.json"

bytes=$(wc -c <"$out/masssprings.wasm")
gzipped=$(gzip -9 -c "$out/masssprings.wasm" | wc -c)
echo "build.sh: $out: masssprings.wasm $bytes bytes, $gzipped gzipped"
