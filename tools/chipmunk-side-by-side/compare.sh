#!/usr/bin/env bash
# Chipmunk2D beside Tamias2D: dumps each scene from the release `tamias`, runs
# it through both engines (one thread each) and prints a markdown table.
#   tools/chipmunk-side-by-side/compare.sh [--no-sleep] [--solver KIND] [SCENE ...]
# Needs PyPI once (a venv with pymunk in .venv here); not used by CI.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
flags=()
while [[ $# -gt 0 && $1 == --* ]]; do
    case $1 in
        --no-sleep) flags+=(--no-sleep); shift ;;
        --solver) flags+=(--solver "$2"); shift 2 ;;
        *) echo "error: unknown option $1" >&2; exit 2 ;;
    esac
done
scenes=("$@")
if [[ ${#scenes[@]} -eq 0 ]]; then
    # Sections A and B of the registry, but for the scenes with joints (not
    # mapped): box2d_tumbler, box2d_spinner.
    scenes=(bowl_circles_100 bowl_circles_500 bowl_circles_1000 bowl_boxes_100 bowl_boxes_500
            bowl_boxes_1000 bowl_hexagons_100 bowl_hexagons_500 bowl_hexagons_1000
            bouncy_circles_500 no_collide pyramid_20 pyramid_100 many_pyramids_4x4
            many_pyramids_10x10 rain_1000 rain_4000 tumbler_500 tumbler_2000
            box2d_large_pyramid box2d_many_pyramids box2d_smash)
fi

venv=$here/.venv
if [[ ! -x $venv/bin/python ]]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q pymunk==7.3.1
fi

cargo build --release -q -p tamias-cli --manifest-path "$root/Cargo.toml"
tamias=$root/target/release/tamias
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for s in "${scenes[@]}"; do
    echo "running $s" >&2
    "$tamias" scene dump "$s" -o "$work/$s.json" >/dev/null
    "$venv/bin/python" "$here/side_by_side.py" "$work/$s.json" --ours "$tamias" --json \
        "${flags[@]}" >>"$work/results.jsonl"
done
"$venv/bin/python" "$here/side_by_side.py" --table "$work/results.jsonl"
