#!/usr/bin/env bash
# The browser test: the demo page (web/) in headless Chromium must compute
# every golden checksum of the registry bit for bit, and its two lockstep
# peers must agree on every confirmed frame (`tamias web --check`, which
# also prints the browser's frame times beside native ones).
#
# Installs what it needs, skipping what is there: Debian's `chromium`
# (needs root, as CI is) and the wasm32-unknown-unknown target (the CLI adds
# it). Extra arguments go to `tamias web --check`, e.g.
#   scripts/browser-test.sh --screenshot docs/images/web-page.png
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v chromium >/dev/null; then
    if [ "$(id -u)" != 0 ]; then
        echo "browser-test: chromium is missing and this is not root: install Debian's chromium" >&2
        exit 1
    fi
    echo "+ apt-get install chromium"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi
# TAMIAS names a `tamias` binary built already (CI passes the one its
# debug tests built: the CLI only serves the page and judges its report,
# the engine the page runs is the wasm build `tamias web` makes; an
# unoptimised `tamias` prints the browser's frame times without native
# ones); otherwise cargo builds and runs an optimised one.
if [ -n "${TAMIAS:-}" ]; then
    "$TAMIAS" web --check "$@"
else
    cargo run --release -q -p tamias-cli -- web --check "$@"
fi
