#!/usr/bin/env bash
# Fails if the engine, the fixtures, the CLI, the GGRS and Bevy crates or the docs send a reader outside
# the repository: to the design notes, the interface specification or the
# scene list kept elsewhere, or to the requirements document (SRS) that is not
# available at all. The repository explains itself: the interface is
# docs/spec-map.md, the design docs/architecture.md, the numbers
# docs/numerics.md, the scenes scenes/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."

paths=()
for p in src docs README.md scenes cli web ggrs bevy; do
    [ -e "$p" ] && paths+=("$p")
done

# `TAMIAS_BENCH_SCENES` (an environment variable of the benches) is not a
# reference, hence the character class before BENCH_SCENES.
pattern='\.\./shared|shared/spec|(^|[^A-Za-z_])BENCH_SCENES|SOLVER_NOTES|DESIGN\.md|DESIGN §|\bSRS\b'

if hits=$(grep -rnIE "$pattern" "${paths[@]}"); then
    echo "References to documents outside the repository:" >&2
    echo "$hits" >&2
    echo "Say it in the repository's own words (docs/spec-map.md, docs/architecture.md, ...)." >&2
    exit 1
fi
echo "no reference outside the repository in ${paths[*]}"
