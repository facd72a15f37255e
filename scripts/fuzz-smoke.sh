#!/usr/bin/env bash
# Short fuzz smoke run for CI: every cargo-fuzz target for FUZZ_SECONDS
# (default 30) from its committed seed corpus. Installs nightly and
# cargo-fuzz if missing. Exits non-zero on any crash.
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${FUZZ_SECONDS:-30}"

if ! rustup toolchain list | grep -q '^nightly'; then
  rustup toolchain install nightly --profile minimal
fi
if ! cargo fuzz --version >/dev/null 2>&1; then
  cargo install cargo-fuzz --locked
fi

targets=$(cargo +nightly fuzz list --fuzz-dir fuzz)
cargo +nightly fuzz build --fuzz-dir fuzz
for t in $targets; do
  # Start from the committed seeds in a scratch directory, so the
  # committed seed set stays small.
  work=$(mktemp -d)
  cp -r "fuzz/seeds/$t/." "$work/" 2>/dev/null || true
  echo "== fuzz $t for ${secs}s"
  cargo +nightly fuzz run --fuzz-dir fuzz "$t" "$work" -- -max_total_time="$secs" -rss_limit_mb=2048 2>&1 | tail -n 3
  rm -rf "$work"
done
echo "fuzz smoke: all targets ran ${secs}s without a crash"
