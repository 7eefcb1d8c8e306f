#!/usr/bin/env bash
# The browser tests of `masssprings view` (viewer.test.mjs,
# teaching.test.mjs and classroom.test.mjs beside this file, one after the
# other): installs what is missing (Debian's chromium, the npm packages
# pinned by package-lock.json), builds the binary, and runs the tests with
# node's test runner. The screenshots go to target/browser/; with
# --update-screenshots, the six docs/viewer.md shows are then copied to
# docs/images/. With --targets, it prints instead the figures of the
# viewer's targets in front of a class (targets.mjs).
#
# With --static, it tests instead the page that runs the simulation itself
# (static.test.mjs: the static build of src/web/build.sh, served by a
# static server); with --static-targets [ROUNDS], it prints that page's
# figures (static-targets.mjs, beside the release program).
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
export CHROMIUM="$(command -v chromium)"
case "${1:-}" in
  --static)
    bash "$root/src/web/build.sh"
    (cd "$root" && cargo build --bin masssprings)
    cd "$here"
    MASSSPRINGS_BIN="$root/target/debug/masssprings" exec node --test static.test.mjs
    ;;
  --static-targets)
    bash "$root/src/web/build.sh"
    (cd "$root" && cargo build --release --bin masssprings)
    cd "$here"
    MASSSPRINGS_BIN="$root/target/release/masssprings" exec node static-targets.mjs "${@:2}"
    ;;
esac
(cd "$root" && cargo build --bin masssprings)

cd "$here"
export MASSSPRINGS_BIN="$root/target/debug/masssprings"
if [ "${1:-}" = "--targets" ]; then
  exec node targets.mjs
fi
node --test --test-concurrency=1 viewer.test.mjs teaching.test.mjs classroom.test.mjs
if [ "${1:-}" = "--update-screenshots" ]; then
  cp "$root/target/browser/viewer.png" "$root/docs/images/viewer.png"
  cp "$root/target/browser/skirt.png" "$root/docs/images/viewer-skirt.png"
  cp "$root/target/browser/compare.png" "$root/docs/images/viewer-compare.png"
  cp "$root/target/browser/without-webgl.png" "$root/docs/images/viewer-without-webgl.png"
  cp "$root/target/browser/projector.png" "$root/docs/images/viewer-projector.png"
  cp "$root/target/browser/phone.png" "$root/docs/images/viewer-phone.png"
  echo "copied target/browser/{viewer,skirt,compare,without-webgl,projector,phone}.png to docs/images/"
fi
