#!/usr/bin/env bash
# Box2D v3 beside Tamias2D: dumps each scene from the release `tamias`, runs
# it through both engines (one thread each) and prints a markdown table.
#   tools/box2d-side-by-side/compare.sh [--no-sleep] [--substeps N] [--solver KIND] [SCENE ...]
# Needs PyPI once (a venv with box2d-python in .venv here); not used by CI.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
flags=()
while [[ $# -gt 0 && $1 == --* ]]; do
    case $1 in
        --no-sleep) flags+=(--no-sleep); shift ;;
        --substeps) flags+=(--substeps "$2"); shift 2 ;;
        --solver) flags+=(--solver "$2"); shift 2 ;;
        *) echo "error: unknown option $1" >&2; exit 2 ;;
    esac
done
scenes=("$@")
if [[ ${#scenes[@]} -eq 0 ]]; then
    scenes=(pyramid_20 pyramid_100 many_pyramids_4x4 bowl_boxes_500 chain_100
            pendulum windmill gear_train spring_mass ratchet rope_bridge ragdolls_20 car)
fi

venv=$here/.venv
if [[ ! -x $venv/bin/python ]]; then
    # box2d-python's wheels need Python 3.12 or newer.
    py=
    for c in python3 python3.13 python3.12 "$(pyenv root 2>/dev/null)"/versions/3.1[2-9]*/bin/python3; do
        if "$c" -c 'import sys; assert sys.version_info >= (3, 12)' 2>/dev/null; then py=$c; break; fi
    done
    [[ -n $py ]] || { echo "error: box2d-python needs Python 3.12 or newer" >&2; exit 1; }
    "$py" -m venv "$venv"
    "$venv/bin/pip" install -q box2d-python==0.1.2
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
