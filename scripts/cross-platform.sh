#!/usr/bin/env bash
# Cross-platform determinism check: runs the golden checksums
# (scenes/tests/golden.rs, values in the scene registry
# scenes/src/registry.rs) on every platform this machine can build and run, and
# fails unless every one passes. Passing everywhere means every platform
# reproduces the same committed 64-bit state checksums, i.e. the engine steps
# bit-identically on all of them.
#
#   platform        how it runs
#   x86_64-debug    native, debug build (overflow checks, debug assertions)
#   x86_64-release  native, release build
#   i686-debug      native 32-bit (i686-unknown-linux-gnu), debug build
#   i686-release    native 32-bit, release build
#   aarch64         aarch64-unknown-linux-gnu, release, under qemu-user
#   wasm32          wasm32-wasip1, release, under node's built-in WASI
#                   (scripts/wasi-run.mjs is the cargo runner)
#   miri-s390x      s390x-unknown-linux-gnu (64-bit big-endian) under Miri
#   miri-i686       i686-unknown-linux-gnu (32-bit) under Miri
#   (Miri runs only the registry's small Miri goldens; see scenes/tests/golden.rs.)
# and opt-in platforms, not in the default set:
#   s390x           s390x-unknown-linux-gnu (big-endian), release, under
#                   qemu-user: the full table, where Miri runs a few steps
#                   (it costs about as much as aarch64 again)
#   i686-parallel   i686 release with the engine's `parallel` feature: the
#                   goldens on 1 thread, then on 3 (one build, two runs)
#   aarch64-parallel  aarch64 release with the `parallel` feature under
#                   qemu-user: the goldens on 3 threads only (a run under
#                   qemu costs half a minute; the threads run every
#                   arithmetic routine the 1-thread step runs, and the
#                   1-thread path runs on every other platform)
# CI runs i686-parallel (instead of i686-release: the same golden check, on
# a build that also has the threads) and miri-s390x; `.ci/run` says why it
# leaves aarch64 to a developer's run.
#
# Usage: scripts/cross-platform.sh [platform...]   (default: all but s390x)
#
# It installs what it needs itself, skipping whatever already works, so a
# re-run is fast:
#   - rustup targets i686-unknown-linux-gnu, aarch64-unknown-linux-gnu,
#     wasm32-wasip1 (stable);
#   - Debian packages (needs root, as CI is): libc6-dev-i386 and
#     lib32gcc-<N>-dev for `gcc -m32` (what gcc-multilib would pull in;
#     gcc-multilib itself conflicts with gcc-aarch64-linux-gnu on Debian),
#     gcc-aarch64-linux-gnu and libc6-dev-arm64-cross, qemu-user (and for
#     s390x: gcc-s390x-linux-gnu, libc6-dev-s390x-cross);
#   - the nightly toolchain's miri and rust-src components ($MIRI_TOOLCHAIN,
#     default `nightly`).
# Node.js (>= 18, with node:wasi) is expected on the machine; if it is
# missing, Debian's nodejs is installed.
#
# A platform whose tooling cannot be installed is reported as FAIL with the
# reason, never skipped, and the script exits non-zero. A summary table
# (platform, wall seconds, CPU seconds, result) closes the run.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)

MIRI_TOOLCHAIN=${MIRI_TOOLCHAIN:-nightly}
DEFAULT_PLATFORMS=(x86_64-debug x86_64-release i686-debug i686-release aarch64 wasm32 miri-s390x miri-i686)
ALL_PLATFORMS=("${DEFAULT_PLATFORMS[@]}" s390x i686-parallel aarch64-parallel)

if [ $# -gt 0 ]; then
    PLATFORMS=("$@")
    for p in "${PLATFORMS[@]}"; do
        case " ${ALL_PLATFORMS[*]} " in
            *" $p "*) ;;
            *)
                echo "cross-platform: unknown platform '$p' (known: ${ALL_PLATFORMS[*]})" >&2
                exit 2
                ;;
        esac
    done
else
    PLATFORMS=("${DEFAULT_PLATFORMS[@]}")
fi

wants() { # wants PREFIX: is a selected platform named PREFIX*?
    local p
    for p in "${PLATFORMS[@]}"; do
        case "$p" in "$1"*) return 0 ;; esac
    done
    return 1
}

now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }
# CPU seconds (user + sys) used by finished child processes so far, into
# $CPU_NOW. `times` must run in this shell: a $(...) subshell has no children.
cpu_now() {
    times >"$TMP/times"
    CPU_NOW=$(awk 'NR == 2 {
        t = 0
        for (i = 1; i <= 2; i++) { split($i, p, /[ms]/); t += p[1] * 60 + p[2] }
        printf "%.1f", t
    }' "$TMP/times")
}
say() { printf '\n=== cross-platform: %s\n' "$*"; }

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# ---------------------------------------------------------------- tooling ---

# Probes: each succeeds only if the tool works, not merely exists.
printf 'int main(void) { return 0; }\n' >"$TMP/probe.c"
i686_links() { gcc -m32 "$TMP/probe.c" -o "$TMP/probe32" 2>/dev/null && "$TMP/probe32"; }
aarch64_links() {
    command -v aarch64-linux-gnu-gcc >/dev/null &&
        aarch64-linux-gnu-gcc "$TMP/probe.c" -o "$TMP/probe64" 2>/dev/null
}
s390x_links() {
    command -v s390x-linux-gnu-gcc >/dev/null &&
        s390x-linux-gnu-gcc "$TMP/probe.c" -o "$TMP/probe390" 2>/dev/null
}
qemu_aarch64() { command -v qemu-aarch64 || command -v qemu-aarch64-static; }
qemu_s390x() { command -v qemu-s390x || command -v qemu-s390x-static; }
node_wasi_ok() {
    command -v node >/dev/null &&
        node -e 'require("node:wasi");
                 process.exit(Number(process.versions.node.split(".")[0]) >= 18 ? 0 : 1)' 2>/dev/null
}
miri_ok() {
    cargo "+$MIRI_TOOLCHAIN" miri --version >/dev/null 2>&1 &&
        rustup "+$MIRI_TOOLCHAIN" component list --installed 2>/dev/null | grep -q '^rust-src'
}

setup_start=$(now)
cpu_now
setup_cpu=$CPU_NOW
say "setup (installs only what is missing)"

# Rust targets (stable).
targets=()
if wants i686; then targets+=(i686-unknown-linux-gnu); fi
if wants aarch64; then targets+=(aarch64-unknown-linux-gnu); fi
if wants s390x; then targets+=(s390x-unknown-linux-gnu); fi
if wants wasm32; then targets+=(wasm32-wasip1); fi
missing_targets=()
installed_targets=$(rustup target list --installed)
for t in "${targets[@]+"${targets[@]}"}"; do
    grep -qx "$t" <<<"$installed_targets" || missing_targets+=("$t")
done
if [ ${#missing_targets[@]} -gt 0 ]; then
    echo "+ rustup target add ${missing_targets[*]}"
    rustup target add "${missing_targets[@]}" || echo "cross-platform: rustup target add failed" >&2
fi

# Debian packages.
apt_pkgs=()
if wants i686 && ! i686_links; then
    apt_pkgs+=(libc6-dev-i386 "lib32gcc-$(gcc -dumpversion | cut -d. -f1)-dev")
fi
if wants aarch64; then
    if ! aarch64_links; then apt_pkgs+=(gcc-aarch64-linux-gnu libc6-dev-arm64-cross); fi
    if ! qemu_aarch64 >/dev/null; then apt_pkgs+=(qemu-user); fi
fi
if wants s390x; then
    if ! s390x_links; then apt_pkgs+=(gcc-s390x-linux-gnu libc6-dev-s390x-cross); fi
    if ! qemu_s390x >/dev/null && [[ " ${apt_pkgs[*]} " != *" qemu-user "* ]]; then apt_pkgs+=(qemu-user); fi
fi
if wants wasm32 && ! command -v node >/dev/null; then apt_pkgs+=(nodejs); fi
if [ ${#apt_pkgs[@]} -gt 0 ]; then
    if [ "$(id -u)" != 0 ]; then
        echo "cross-platform: not root: cannot apt-get install ${apt_pkgs[*]}" >&2
    else
        echo "+ apt-get install ${apt_pkgs[*]}"
        export DEBIAN_FRONTEND=noninteractive
        if ! { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${apt_pkgs[@]}"; }; then
            echo "cross-platform: apt-get install ${apt_pkgs[*]} failed" >&2
            if [[ " ${apt_pkgs[*]} " == *" qemu-user "* ]]; then
                # Some Debian releases ship qemu-aarch64 only as qemu-user-static.
                apt-get install -y -qq --no-install-recommends qemu-user-static || true
            fi
        fi
    fi
fi

# Miri (nightly).
if wants miri && ! miri_ok; then
    if rustup toolchain list | grep -q "^$MIRI_TOOLCHAIN"; then
        echo "+ rustup +$MIRI_TOOLCHAIN component add miri rust-src"
        rustup "+$MIRI_TOOLCHAIN" component add miri rust-src || true
    else
        echo "+ rustup toolchain install $MIRI_TOOLCHAIN --profile minimal --component miri,rust-src"
        rustup toolchain install "$MIRI_TOOLCHAIN" --profile minimal --component miri,rust-src || true
    fi
fi

# Verify, per platform: an empty reason means the platform can run.
declare -A TOOLING
installed_targets=$(rustup target list --installed)
has_target() { grep -qx "$1" <<<"$installed_targets"; }
for p in "${PLATFORMS[@]}"; do
    reason=""
    case "$p" in
        i686-*)
            has_target i686-unknown-linux-gnu || reason="rust target i686-unknown-linux-gnu not installed"
            [ -n "$reason" ] || i686_links || reason="gcc -m32 cannot link (libc6-dev-i386, lib32gcc-N-dev)"
            ;;
        aarch64 | aarch64-parallel)
            has_target aarch64-unknown-linux-gnu || reason="rust target aarch64-unknown-linux-gnu not installed"
            [ -n "$reason" ] || aarch64_links ||
                reason="aarch64-linux-gnu-gcc cannot link (gcc-aarch64-linux-gnu, libc6-dev-arm64-cross)"
            [ -n "$reason" ] || qemu_aarch64 >/dev/null || reason="qemu-aarch64 not found (qemu-user)"
            [ -n "$reason" ] || "$(qemu_aarch64)" -L /usr/aarch64-linux-gnu "$TMP/probe64" ||
                reason="qemu-aarch64 cannot run an aarch64 binary"
            ;;
        s390x)
            has_target s390x-unknown-linux-gnu || reason="rust target s390x-unknown-linux-gnu not installed"
            [ -n "$reason" ] || s390x_links ||
                reason="s390x-linux-gnu-gcc cannot link (gcc-s390x-linux-gnu, libc6-dev-s390x-cross)"
            [ -n "$reason" ] || qemu_s390x >/dev/null || reason="qemu-s390x not found (qemu-user)"
            [ -n "$reason" ] || "$(qemu_s390x)" -L /usr/s390x-linux-gnu "$TMP/probe390" ||
                reason="qemu-s390x cannot run an s390x binary"
            ;;
        wasm32)
            has_target wasm32-wasip1 || reason="rust target wasm32-wasip1 not installed"
            [ -n "$reason" ] || node_wasi_ok || reason="node >= 18 with node:wasi not found"
            ;;
        miri-*)
            miri_ok || reason="cargo +$MIRI_TOOLCHAIN miri (components miri, rust-src) not available"
            ;;
    esac
    TOOLING[$p]=$reason
    if [ -n "$reason" ]; then echo "cross-platform: $p: TOOLING MISSING: $reason" >&2; fi
done

# The golden test (scenes/tests/golden.rs) uses only tamias2d-scenes, whose
# dependencies are tamias2d, fixed, serde and serde_json (its optional
# features stay off). Every platform builds it from a generated package,
# target/cross-platform/runner (target dir target/cross-platform/target),
# whose one test target is scenes/tests/golden.rs and whose one dependency is
# tamias2d-scenes, with the workspace's Cargo.lock, [profile.*] and
# [patch.*]: the library compiles exactly as for `cargo test`, but no
# dev-dependency of the workspace (rapier2d, criterion, proptest, ggrs ...)
# is built. They are most of the compile time, proptest's default `fork`
# feature does not build for wasm32-wasip1, criterion builds C code (alloca)
# that needs a C compiler for the target (there is none for s390x), and a
# half-edited example or bench elsewhere cannot break this check. `cargo
# test` itself runs the same test on x86_64.
RUNNER_DIR=${CARGO_TARGET_DIR:-$ROOT/target}/cross-platform/runner
RUNNER_TARGET_DIR=${CARGO_TARGET_DIR:-$ROOT/target}/cross-platform/target
mkdir -p "$RUNNER_DIR"
{
    cat <<EOF
# Generated by scripts/cross-platform.sh: scenes/tests/golden.rs alone,
# without any dev-dependency. Do not edit.
[package]
name = "tamias2d-golden-runner"
version = "0.0.0"
edition = "2021"
publish = false
autotests = false

[dependencies]
tamias2d-scenes = { path = '$ROOT/scenes' }
tamias2d = { path = '$ROOT' }

# The *-parallel platforms: the engine's parallel step, the goldens computed
# on TAMIAS_GOLDEN_THREADS threads.
[features]
parallel = ["tamias2d/parallel"]

[[test]]
name = "golden"
path = '$ROOT/scenes/tests/golden.rs'

[workspace]

EOF
    # Profiles and patches come from the root manifest of a build: copy the crate's.
    awk '/^\[/ { copy = ($0 ~ /^\[(profile|patch)\./) } copy' "$ROOT/Cargo.toml"
} >"$RUNNER_DIR/Cargo.toml"
if [ -f "$ROOT/Cargo.lock" ]; then cp "$ROOT/Cargo.lock" "$RUNNER_DIR/Cargo.lock"; fi

setup_time=$(since "$setup_start" "$(now)")
cpu_now
setup_cpu=$(since "$setup_cpu" "$CPU_NOW")

# ------------------------------------------------------------------- runs ---

show() { # prints the command with the variables it is given, then runs it
    local v
    for v in CARGO_TARGET_DIR CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER \
        CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_LINKER \
        CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_RUNNER CARGO_TARGET_WASM32_WASIP1_RUNNER; do
        if [ -n "${!v:-}" ]; then echo "+ $v=\"${!v}\""; fi
    done
    echo "+ $*"
    "$@"
}
runner() { # runner CARGO-COMMAND...: the golden test of the generated runner package
    CARGO_TARGET_DIR=$RUNNER_TARGET_DIR show "$@" --manifest-path "$RUNNER_DIR/Cargo.toml" --test golden \
        ${NOCAPTURE:+-- --nocapture}
}
# Cargo runners and linkers go through the environment, so that normal
# `cargo build` / `cargo test` on x86_64 never see them.
run_platform() {
    local qemu
    case "$1" in
        x86_64-debug) runner cargo test ;;
        x86_64-release) runner cargo test --release ;;
        i686-debug) runner cargo test --target i686-unknown-linux-gnu ;;
        i686-release) runner cargo test --release --target i686-unknown-linux-gnu ;;
        i686-parallel)
            # One build, two runs (the second builds nothing): 1 thread, then 3.
            runner cargo test --release --target i686-unknown-linux-gnu --features parallel &&
                TAMIAS_GOLDEN_THREADS=3 runner cargo test --release --target i686-unknown-linux-gnu \
                    --features parallel
            ;;
        aarch64-parallel)
            qemu=$(qemu_aarch64)
            (
                export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc \
                    CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="$qemu -L /usr/aarch64-linux-gnu"
                TAMIAS_GOLDEN_THREADS=3 runner cargo test --release --target aarch64-unknown-linux-gnu \
                    --features parallel
            )
            ;;
        aarch64)
            qemu=$(qemu_aarch64)
            CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc \
                CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="$qemu -L /usr/aarch64-linux-gnu" \
                runner cargo test --release --target aarch64-unknown-linux-gnu
            ;;
        s390x)
            qemu=$(qemu_s390x)
            CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_LINKER=s390x-linux-gnu-gcc \
                CARGO_TARGET_S390X_UNKNOWN_LINUX_GNU_RUNNER="$qemu -L /usr/s390x-linux-gnu" \
                runner cargo test --release --target s390x-unknown-linux-gnu
            ;;
        wasm32)
            # wasm32-wasip1 aborts on panic, so libtest never prints a
            # captured failure message: --nocapture lets the test print it.
            CARGO_TARGET_WASM32_WASIP1_RUNNER="node --no-warnings $ROOT/scripts/wasi-run.mjs" \
                NOCAPTURE=1 runner cargo test --release --target wasm32-wasip1
            ;;
        miri-s390x) runner cargo "+$MIRI_TOOLCHAIN" miri test --target s390x-unknown-linux-gnu ;;
        miri-i686) runner cargo "+$MIRI_TOOLCHAIN" miri test --target i686-unknown-linux-gnu ;;
    esac
}

declare -A RESULT TIME CPU
failed=0
for p in "${PLATFORMS[@]}"; do
    if [ -n "${TOOLING[$p]}" ]; then
        RESULT[$p]="FAIL (tooling: ${TOOLING[$p]})"
        TIME[$p]=-
        CPU[$p]=-
        failed=1
        continue
    fi
    say "$p"
    start=$(now)
    cpu_now
    cpu_start=$CPU_NOW
    if run_platform "$p"; then
        RESULT[$p]=pass
    else
        RESULT[$p]=FAIL
        failed=1
    fi
    TIME[$p]=$(since "$start" "$(now)")
    cpu_now
    CPU[$p]=$(since "$cpu_start" "$CPU_NOW")
    echo "=== cross-platform: $p: ${RESULT[$p]} in ${TIME[$p]} s (${CPU[$p]} CPU s)"
done

# ---------------------------------------------------------------- summary ---

echo
echo "=== cross-platform summary: golden checksums (scenes/tests/golden.rs) per platform"
row() { printf '%-16s %9s %9s  %s\n' "$@"; }
row platform "wall s" "CPU s" result
row setup "$setup_time" "$setup_cpu" "done"
for p in "${PLATFORMS[@]}"; do
    row "$p" "${TIME[$p]}" "${CPU[$p]}" "${RESULT[$p]}"
done
cpu_now
row total "$(since "$setup_start" "$(now)")" "$CPU_NOW" "$([ $failed = 0 ] && echo 'all pass' || echo FAILED)"
if [ $failed != 0 ]; then
    echo "cross-platform: FAILED: a platform above did not reproduce the goldens or could not run" >&2
    exit 1
fi
echo "cross-platform: every platform reproduces the golden checksums"
