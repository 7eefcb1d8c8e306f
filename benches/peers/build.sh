#!/bin/sh
# Builds ./cholmod_peer, the SuiteSparse (AMD + CHOLMOD) peer benchmark.
# Needs gcc and SuiteSparse (Debian: apt-get install -y libsuitesparse-dev).
set -e
cd "$(dirname "$0")"
CFLAGS=${CFLAGS:-"-O3 -march=native -std=c11 -Wall -Wextra"}
SUITESPARSE_INC=${SUITESPARSE_INC:-/usr/include/suitesparse}
gcc $CFLAGS -I"$SUITESPARSE_INC" -o cholmod_peer cholmod_peer.c \
    -lcholmod -lamd -lsuitesparseconfig -lm
echo "built $(pwd)/cholmod_peer with: gcc $CFLAGS"
