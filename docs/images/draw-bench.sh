#!/usr/bin/env bash
# Redraws the scaling plot of docs/performance.md (section 4) and prints the
# table the chapter quotes: every grid-N cloth from 32 to 2000, each size in
# a fresh process. About 4 minutes and 5 GB of memory; run it on a quiet
# machine, since it measures time.
#
#     bash docs/images/draw-bench.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release --quiet
target/release/masssprings bench --sizes 32,100,316,1000,2000 --steps 2 --plot docs/images/bench.png
