#!/usr/bin/env bash
# Redraws the viewer's two screenshots (viewer.png, viewer-skirt.png) of
# docs/viewer.md: the browser test drives the viewer in headless Chromium
# and copies its screenshots here. Installs Chromium and its npm package
# when they are missing (see tests/browser/run.sh).
#
#     bash docs/images/screenshots.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
exec tests/browser/run.sh --update-screenshots
