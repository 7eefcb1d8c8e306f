#!/usr/bin/env bash
# Ours beside the peers, in one session, interleaved: the figures of
# docs/performance.md.
#
#   benches/peers/compare.sh [ROUNDS]      (default 5 rounds)
#
# Needs: ../shared (the assignment's scenes and tools/eigen-ref), g++ with
# Eigen 3.4 (apt-get install -y libeigen3-dev), SuiteSparse
# (apt-get install -y libsuitesparse-dev), python3, and cargo for the faer
# peer (benches/peers/faer_peer, its own crate: faer is fetched there, never
# a dependency of masssprings). Each round runs, for each matrix, our
# `masssprings analyze`, then `cholmod_peer`, then `faer_peer`, and for each
# scene our `masssprings simulate` then `eigen-ref bench`, so that every
# pair is measured seconds apart; the summary gives the median over rounds
# of each figure and the ratio ours / peer. The grids are the scaling sizes
# of `masssprings bench` (32, 100, 316); LARGE=1 adds grid-1000 (minutes),
# SIDES="..." replaces the list. Set NO_FAER=1 to skip faer. Ours uses
# the simulation's supernodes (small ones merged) unless SUPERNODES=
# fundamental|relaxed says otherwise. Ours and faer run on one thread, and
# again on THREADS (default 2) threads: ours with `--threads`, faer with
# `Par::rayon(THREADS)`; THREADS=1 skips the second runs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
shared="$root/../shared"
rounds="${1:-5}"
work="${WORK:-${TMPDIR:-/tmp}/masssprings-compare}"
mkdir -p "$work"

# --- build everything -------------------------------------------------------
(cd "$root" && cargo build --release --quiet)
ours="$root/target/release/masssprings"
[ -x "$here/cholmod_peer" ] || "$here/build.sh" >/dev/null
faer="$here/faer_peer/target/release/faer_peer"
[ "${NO_FAER:-0}" = 1 ] || (cd "$here/faer_peer" && cargo build --release --quiet)
if [ ! -x "$work/eigen-ref/ref" ]; then
    rm -rf "$work/eigen-ref" && cp -r "$shared/tools/eigen-ref" "$work/eigen-ref"
    chmod -R u+w "$work/eigen-ref" && (cd "$work/eigen-ref" && ./build.sh >/dev/null)
fi
eigen="$work/eigen-ref/ref"
# CHOLMOD's supernodal code calls BLAS: use a single-threaded OpenBLAS when
# installed (apt-get install -y libopenblas0-serial), see README.md here.
serial_blas=/usr/lib/x86_64-linux-gnu/openblas-serial
[ -d "$serial_blas" ] && export LD_LIBRARY_PATH="$serial_blas${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

# --- the matrices and scenes ------------------------------------------------
sides="${SIDES:-32 100 316}"
[ "${LARGE:-0}" = 1 ] && sides="$sides 1000"
scenes=""
for name in flag skirt; do
    cp "$shared/original-data/$name".* "$work/" 2>/dev/null || true
    cp "$shared/original-data/"*.png "$work/" 2>/dev/null || true
    scenes="$scenes $work/$name.json"
done
for n in $sides; do
    "$ours" generate grid "$n" --out "$work" >/dev/null
    scenes="$scenes $work/grid-$n.json"
done
for scene in $scenes; do
    base="${scene%.json}"
    [ -f "$base.mtx" ] || "$eigen" export-q "$scene" "$base.mtx" >/dev/null
done

# --- interleaved rounds -----------------------------------------------------
out="$work/results.jsonl"
supernodes="${SUPERNODES:-small}"
threads="${THREADS:-2}"
: > "$out"
for round in $(seq "$rounds"); do
    for scene in $scenes; do
        base="${scene%.json}"
        name="$(basename "$base")"
        echo "round $round/$rounds: $name" >&2
        echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"ours\",\"data\":$("$ours" analyze "$base.mtx" --supernodes "$supernodes" --threads 1 --json)}" >>"$out"
        if [ "$threads" != 1 ]; then
            echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"ours-threads\",\"data\":$("$ours" analyze "$base.mtx" --supernodes "$supernodes" --threads "$threads" --json)}" >>"$out"
        fi
        echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"cholmod\",\"data\":$("$here/cholmod_peer" "$base.mtx" 11 --json)}" >>"$out"
        if [ "${NO_FAER:-0}" != 1 ]; then
            echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"faer\",\"data\":$("$faer" "$base.mtx" 11 --json)}" >>"$out"
            if [ "$threads" != 1 ]; then
                echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"faer-threads\",\"data\":$("$faer" "$base.mtx" 11 --json --threads "$threads")}" >>"$out"
            fi
        fi
        steps=30
        [ "$name" = grid-1000 ] && steps=3
        echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"ours-step\",\"data\":$("$ours" simulate "$scene" --steps "$steps" --supernodes "$supernodes" --threads 1 --json)}" >>"$out"
        if [ "$threads" != 1 ]; then
            echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"ours-step-threads\",\"data\":$("$ours" simulate "$scene" --steps "$steps" --supernodes "$supernodes" --threads "$threads" --json)}" >>"$out"
        fi
        csv="$("$eigen" bench "$scene" 120 | grep '^CSV,')"
        echo "{\"round\":$round,\"matrix\":\"$name\",\"tool\":\"eigen\",\"data\":{\"csv\":\"$csv\"}}" >>"$out"
    done
done

python3 "$here/summarize.py" "$out"
