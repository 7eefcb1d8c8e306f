#!/usr/bin/env bash
# The tests of the page's WebAssembly module under node, no browser needed
# (module.test.mjs beside this file): builds the page's folder
# (src/web/build.sh) and the program, then runs them. With --targets, it
# prints instead the figures of the page's targets that need no browser
# (targets.mjs: the module's size, its step time beside the native
# program's with the portable kernels), with the release program.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"

bash "$root/src/web/build.sh"
export MASSSPRINGS_WASM="$root/target/web/masssprings.wasm"
if [ "${1:-}" = "--targets" ]; then
  (cd "$root" && cargo build --release --bin masssprings)
  MASSSPRINGS_BIN="$root/target/release/masssprings" exec node "$here/targets.mjs" "${@:2}"
fi
(cd "$root" && cargo build --bin masssprings)
MASSSPRINGS_BIN="$root/target/debug/masssprings" node --test "$here/module.test.mjs"
