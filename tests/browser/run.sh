#!/usr/bin/env bash
# The browser test of `masssprings view` (viewer.test.mjs beside this file):
# installs what is missing (Debian's chromium, the npm packages pinned by
# package-lock.json), builds the binary, and runs the test with node's test
# runner. The screenshots go to target/browser/; with --update-screenshots,
# the two docs/viewer.md shows are then copied to docs/images/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"

if ! command -v chromium >/dev/null 2>&1; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -q
  $sudo apt-get install -y -q chromium
fi
if [ ! -d "$here/node_modules" ]; then
  (cd "$here" && npm ci --no-audit --no-fund)
fi
(cd "$root" && cargo build --bin masssprings)

cd "$here"
MASSSPRINGS_BIN="$root/target/debug/masssprings" CHROMIUM="$(command -v chromium)" \
  node --test viewer.test.mjs
if [ "${1:-}" = "--update-screenshots" ]; then
  cp "$root/target/browser/viewer.png" "$root/docs/images/viewer.png"
  cp "$root/target/browser/skirt.png" "$root/docs/images/viewer-skirt.png"
  echo "copied target/browser/{viewer,skirt}.png to docs/images/"
fi
