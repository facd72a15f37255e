#!/usr/bin/env bash
# Short fuzz smoke run for CI: every cargo-fuzz target for FUZZ_SECONDS
# (default 30) from its committed seed corpus, two at a time. Installs
# nightly and cargo-fuzz if missing. Exits non-zero on any crash.
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${FUZZ_SECONDS:-30}"

if ! rustup toolchain list | grep -q '^nightly'; then
  rustup toolchain install nightly --profile minimal
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
  # A debug build of the tool: it builds in half the time, and its own
  # speed is nothing beside the targets'.
  cargo install cargo-fuzz --locked --debug
fi

targets=$(cargo +nightly fuzz list --fuzz-dir fuzz)
# No sanitizer: every target's code is safe Rust (bounds and overflow
# checked; the fuzz build keeps debug assertions and overflow checks) but
# the AVX2 operations of tamias2d-simd, which take and return values and
# touch no memory through pointers, so AddressSanitizer has nothing to
# find; it cost the build and the runs time.
# A smoke run is short, so the targets build for a short build: 16
# codegen units (cargo-fuzz's default is one) and optimisation level 1.
# Both cut the build by 40 % and the runs' speed by little (the
# same order of runs in five seconds). `cargo fuzz run` gets the same
# settings, or it would build the targets again.
build=(--sanitizer none --codegen-units 16)
export CARGO_PROFILE_RELEASE_OPT_LEVEL=1
cargo +nightly fuzz build "${build[@]}" --fuzz-dir fuzz
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
run_target() { # run_target NAME: one target from its seeds, its report on failure
  local t=$1 work
  # Start from the committed seeds in a scratch directory, so the
  # committed seed set stays small.
  work=$(mktemp -d)
  cp -r "fuzz/seeds/$t/." "$work/" 2>/dev/null || true
  if cargo +nightly fuzz run "${build[@]}" --fuzz-dir fuzz "$t" "$work" -- \
    -max_total_time="$secs" -rss_limit_mb=2048 >"$logs/$t" 2>&1; then
    echo "== fuzz $t: ${secs}s, no crash ($(grep -o 'Done [0-9]* runs' "$logs/$t" | tail -n 1))"
  else
    echo "== fuzz $t: FAILED"
    tail -n 60 "$logs/$t"
    rm -rf "$work"
    return 1
  fi
  rm -rf "$work"
}
# Two targets at a time: a fuzzer runs on one core.
# Each runs for the same time, so waiting for the older one loses little.
failed=0
pids=()
for t in $targets; do
  run_target "$t" &
  pids+=("$!")
  if [ "${#pids[@]}" -ge 2 ]; then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
if [ "$failed" != 0 ]; then
  echo "fuzz smoke: a target failed" >&2
  exit 1
fi
echo "fuzz smoke: all targets ran ${secs}s without a crash"
