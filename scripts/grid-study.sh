#!/usr/bin/env bash
# The narrow lane grid's quality study (docs/numerics.md, "The narrow lane
# grid"): runs perf/src/bin/grid_study.rs in the default build, the
# `grid-study-constants` build (the soft contact rows' constants on 32-bit
# lane grids), the `grid-study-reads` build (the velocities a row reads
# too), the `grid-study-fine` and `grid-study` builds (every lane value,
# impulses on Q8.24 and Q16.16), and prints their measures side by side as
# a Markdown table (about 12 minutes).
# Arguments are scene names (default: the program's list). Run from the
# repository root.
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/grid_study
mkdir -p "$out"
builds=(full grid-study-constants grid-study-reads grid-study-fine grid-study)
for b in "${builds[@]}"; do
    features=()
    [[ $b == full ]] || features=(--features "$b")
    cargo run -q --release -p tamias2d-perf --bin grid_study "${features[@]}" -- "$@" > "$out/$b.tsv"
done
echo "| scene | measure | full precision: median [range] | narrow constants | narrow reads | all narrow, Q8.24 impulses | all narrow, Q16.16 impulses |"
echo "|---|---|---:|---:|---:|---:|---:|"
# A narrow build's range apart from the full build's is marked with "≠".
files=()
for b in "${builds[@]}"; do files+=("$out/$b.tsv"); done
paste "${files[@]}" > "$out/all.tsv"
awk -F '\t' '
function cell(k,    med, lo, hi, apart) {
    med = $(5 * k + 3); lo = $(5 * k + 4); hi = $(5 * k + 5)
    apart = (lo > $5 || hi < $4) ? " ≠" : ""
    return sprintf("%s [%s, %s]%s", med, lo, hi, apart)
}
{
    for (k = 1; k < 5; k++) if ($(5 * k + 1) != $1 || $(5 * k + 2) != $2) { print "mismatched lines: " $0 > "/dev/stderr"; exit 1 }
    m = $2; gsub(/\|/, "\\|", m)
    if ($2 == "checksum") {
        printf "| `%s` | %s | `%s` | `%s` | `%s` | `%s` | `%s` |\n", $1, m, $3, $8, $13, $18, $23
        next
    }
    printf "| `%s` | %s | %s [%s, %s] | %s | %s | %s | %s |\n", $1, m, $3, $4, $5, cell(1), cell(2), cell(3), cell(4)
}' "$out/all.tsv"
