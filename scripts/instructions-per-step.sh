#!/usr/bin/env bash
# Instructions per step of built-in scenes on one thread, under callgrind:
# (I(2N steps) − I(N steps)) / N with the release CLI, so loading the scene
# and the process's start cancel out. Instruction counts are the stable
# figure on a shared VM (times are not).
#
#   scripts/instructions-per-step.sh [N] SCENE...
#   scripts/instructions-per-step.sh 100 pyramid_20 bowl_boxes_500 chain_100
#
# Needs valgrind; builds the CLI with the `measure` profile (release with
# one codegen unit, so the count does not move with how the compiler splits
# the crate into units), or runs the binary TAMIAS_BIN names (to compare
# two builds). TAMIAS_ARGS adds arguments to every run (e.g.
# TAMIAS_ARGS="--solver soft"). The soft step's contact passes run on the
# scalar kernels (TAMIAS_KERNELS, default `scalar`): valgrind 3 cannot
# decode some of the AVX instructions of the wide kernels, and the run
# would stop at the first (a count of 0).
set -euo pipefail
cd "$(dirname "$0")/.."
n=100
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then n=$1; shift; fi
bin=${TAMIAS_BIN:-}
if [[ -z "$bin" ]]; then
    cargo build --profile measure -q -p tamias-cli
    bin=target/measure/tamias
fi
out=$(mktemp -d)
total() { # total SCENE STEPS: the instructions of the whole run
    valgrind --tool=callgrind --callgrind-out-file="$out/cg" "$bin" run "$1" --steps "$2" --threads 1 \
        --kernels "${TAMIAS_KERNELS:-scalar}" ${TAMIAS_ARGS:-} >/dev/null 2>&1
    awk '/^summary:/ {print $2}' "$out/cg"
}
for scene in "$@"; do
    a=$(total "$scene" "$n")
    b=$(total "$scene" $((2 * n)))
    echo "$scene: $(( (b - a) / n )) instructions per step (steps $n..$((2 * n)))"
done
rm -rf "$out"
