#!/usr/bin/env bash
# Redraws the viewer's six screenshots of docs/viewer.md (viewer.png,
# viewer-skirt.png, viewer-compare.png: the assignment beside converged
# steps, viewer-without-webgl.png: the page drawn by the crate's renderer,
# viewer-projector.png: a settled comparison at 1024 × 768 in large print,
# viewer-phone.png: the page at 390 × 844 with its panels folded):
# the browser tests drive the viewer in headless Chromium and copy their
# screenshots here. Installs Chromium and its npm package
# when they are missing (see tests/browser/run.sh).
#
#     bash docs/images/screenshots.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
exec tests/browser/run.sh --update-screenshots
