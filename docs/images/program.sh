# The program the picture scripts run (sourced by render-all.sh,
# mistakes.sh, draw-sparsity.sh): by default the test profile's binary,
# target/debug/masssprings, the one `cargo test` builds and runs, so that
# after an edit the tests and a picture share one build. MASSSPRINGS=PATH
# overrides it (e.g. target/release/masssprings). The pictures do not
# depend on the build: every build does the same arithmetic. Timings do, so
# the scripts that draw timings (draw-bench.sh, converge-all.sh) and the
# benches use the release build.
if [ -z "${MASSSPRINGS:-}" ]; then
    cargo build --quiet --bin masssprings
    MASSSPRINGS=target/debug/masssprings
fi
