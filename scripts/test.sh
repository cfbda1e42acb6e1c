#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every test: the suite in a release build, again under AddressSanitizer +
# UndefinedBehaviorSanitizer (all but the long pipelines and the heavy tests), the libFuzzer
# targets briefly (clang), the device's package (amd64) through a real kernel in a VM, and the
# device-only build (no offline dependency) cross-compiled for arm64 (a Raspberry Pi) with its
# tests under qemu-aarch64.
# Installs missing packages. This is what CI runs; each stage's time is printed.
#   scripts/test.sh --quick   a developer's loop: the release build and its tests labelled
#                             unit, gpu or data (not slow; see cmake/VpeTests.cmake), no
#                             sanitizers, fuzzing or device build
# It starts with the style check (scripts/check-format.sh). Every configure is followed by the
# dependency audit (scripts/audit-deps.sh): a file the build found that no package in
# scripts/install-deps.sh brings fails the run, so a package installed by hand on this machine
# cannot hide a broken fresh install.
# CI allows 90 minutes on 2 cores, so the extra builds compile only what they test: the
# sanitizer presets at -O1 -g1 (line tables are enough for the reports; at -O2 -g the ASan
# build took ~15 min, relight_web_encoder.cpp alone 97 s against 27 s) and with clang (GCC's
# sanitizer instrumentation compiled 3.3-3.5x slower: relight_web_encoder.cpp 56.5 s of CPU
# against 16.4 s, docs/ci-budget.md), and the fuzz preset only its four fuzzers and the rooms
# they link (46 files, not the whole tree again).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/debian-root.sh  # removing the package tests' roots
source scripts/lib/root-cache.sh  # the report names the roots' cache
quick=0
for argument in "$@"; do
    case "$argument" in
        --quick) quick=1 ;;
        *) echo "test.sh: unknown option $argument (--quick)" >&2; exit 2 ;;
    esac
done
scripts/install-deps.sh --test
[[ $quick -eq 1 ]] || scripts/install-deps.sh --arm64

jobs=$(nproc)

# Every build compiles through one compile cache per machine, outside the clone
# (scripts/lib/compile-cache.sh says where and why its keys cannot go stale).
source scripts/lib/compile-cache.sh
compile_cache_use "$PWD"
source scripts/lib/test-run-report.sh
test_run_begin

# The Debian roots of the device's checks (scripts/device-roots.sh: the arm64 sysroot, the VM's
# and the arm64 package check's base roots; on an empty roots' cache about 770 s, mostly
# downloading and unpacking packages) are made in the background while the builds below run,
# instead of in the stages that use them. Its own process group, so that a failing run stops it.
roots_pid=""
if [[ $quick -eq 0 ]]; then
    # One state of Debian's archive for the whole run, read now: the roots made in the
    # background and those made or restored by the stages then share their keys.
    roots_sources=$(mktemp -d /tmp/vpe-roots-sources.XXXXXX)
    (debian_root_sources "$roots_sources" && root_cache_archive_state "$mirror") \
        >"$roots_sources/state" || true
    export VPE_ROOT_ARCHIVE_STATE=$(cat "$roots_sources/state")
    rm -rf "$roots_sources"
    roots_log=$(mktemp /tmp/vpe-device-roots.XXXXXX)
    setsid scripts/device-roots.sh >"$roots_log" 2>&1 &
    roots_pid=$!
fi
# When the run ends, passed or not: the background roots stopped, then the run's report.
finish() {
    local status=$?
    [[ -n $roots_pid ]] && kill -- -"$roots_pid" 2>/dev/null
    # The report never changes the run's status (a pipe it closes early, say).
    test_run_summary "$status" || echo "test.sh: the run's report failed (exit $?)" >&2
    exit "$status"
}
trap finish EXIT
# configure PRESET [AUDIT OPTIONS]: configure with CMake's file API asked for, then audit what
# it found.
configure() {
    local preset=$1; shift
    scripts/audit-deps.sh query "build/$preset"
    cmake --preset "$preset" >/dev/null
    scripts/audit-deps.sh check "$@" "build/$preset"
}
# audit_headers PRESET [AUDIT OPTIONS]: after building, also every system header the compiler
# read.
audit_headers() { local preset=$1; shift; scripts/audit-deps.sh check --headers "$@" "build/$preset"; }

# Every test must carry a label (cmake/VpeTests.cmake), or the quick path would miss it.
check_labels() {
    local unlabelled
    unlabelled=$(ctest --test-dir "build/$1" -N -LE '^(unit|gpu|slow|data|fuzz)$' | sed -n 's/^ *Test *#[0-9]*: //p')
    if [[ -n "$unlabelled" ]]; then
        echo "test.sh: tests without a label in build/$1 (cmake/VpeTests.cmake):" $unlabelled >&2
        exit 1
    fi
}

test_run_stage "style (clang-format)"
scripts/check-format.sh

test_run_stage "release build and tests"
configure release
test_run_built release
cmake --build --preset release -j "$jobs"
audit_headers release
check_labels release
if [[ $quick -eq 1 ]]; then
    test_run_ctest release --preset release -j "$jobs" -LE '^(slow|fuzz)$'
    test_run_close_stage
    echo "quick tests passed (the full run: scripts/test.sh)" >&2
    exit 0
fi
test_run_ctest release --preset release -j "$jobs"

test_run_stage "ASan + UBSan build and tests"
configure asan
test_run_built asan
cmake --build --preset asan -j "$jobs"
# The tests labelled slow are whole pipelines through the CLI (synth, scan, fit, bake, render),
# whose units run under the sanitizers in their own tests; of them only the bad-input ones run
# here, error paths being where sanitizers find the most. The other slow tests (~330 s in the
# release build, ~3x that under ASan) ran in the release build above: CI allows 90 minutes.
# The installation's refusals are left to the release build too: each first simulates a whole
# scan, the longest of these refusals by far, and the scan's, registration's and bake's
# refusals run here on their own.
# The tests labelled heavy (cmake/VpeTests.cmake) ran in the release build too: ASan made
# each of them minutes long, and smaller tests take their code paths here.
ASAN_OPTIONS=detect_leaks=1 test_run_ctest asan --preset asan -j "$jobs" -LE '^(slow|heavy)$'
ASAN_OPTIONS=detect_leaks=1 test_run_ctest asan --preset asan -j "$jobs" -L '^slow$' -R 'BadInput|Refuse' \
    -E '^Install[.]'

test_run_stage "libFuzzer targets (clang)"
configure fuzz
test_run_built fuzz
cmake --build --preset fuzz -j "$jobs" --target vpe_fuzzers
# Each fuzzer runs for a fixed wall time on one core (VPE_FUZZ_SECONDS): side by side they
# fuzz as long each, in half the time.
test_run_ctest fuzz --test-dir build/fuzz -j "$jobs" --output-on-failure

test_run_stage "device package (amd64) and its KMS path in a VM"
# The roots made in the background since the start (the VM's, the arm64 sysroot and package root).
roots_status=0
wait "$roots_pid" || roots_status=$?
roots_pid=""
cat "$roots_log" >&2
rm -f "$roots_log"
if [[ $roots_status -ne 0 ]]; then
    echo "test.sh: scripts/device-roots.sh failed (exit $roots_status; its output above)" >&2
    exit 1
fi
# The device-only build without its tests (preset device-package): the release build above ran
# the device's tests, and the arm64 build below runs them again without any offline
# dependency. cpack: vpe-player_<version>_amd64.deb (docs/device-package.md); its contents
# checked, then Debian's kernel in qemu (TCG) with a virtio-gpu drives the packaged player
# (docs/kms-vm.md).
configure device-package
test_run_built device-package
cmake --build --preset device-package -j "$jobs"
audit_headers device-package
rm -f build/device-package/vpe-player_*.deb
(cd build/device-package && cpack >/dev/null)
scripts/package-check.sh --contents-only amd64 build/device-package/vpe-player_*_amd64.deb
vm_work=$(mktemp -d /tmp/vpe-kms-vm.XXXXXX)  # kept for a look when the check fails
scripts/kms-vm-check.sh "$vm_work" build/device-package/vpe-player_*_amd64.deb
debian_root_remove "$vm_work/root"
rm -rf --one-file-system "$vm_work"

test_run_stage "arm64: device build for a Pi, its tests under qemu-aarch64"
# Against a Debian 12 arm64 root holding only the device's packages (scripts/arm64-sysroot.sh),
# made in the background since the start.
configure device-arm64 --sysroot build/arm64-root
test_run_built device-arm64
cmake --build --preset device-arm64 -j "$jobs"
audit_headers device-arm64 --sysroot build/arm64-root
check_labels device-arm64
# The preset leaves out the tests labelled realtime (cmake/VpeTests.cmake): emulation is far
# slower than a Pi, and they ran above on amd64.
echo "arm64: left out under emulation (label realtime):" \
    $(ctest --test-dir build/device-arm64 -N -L '^realtime$' | sed -n 's/^ *Test *#[0-9]*: //p') >&2
test_run_ctest device-arm64 --preset device-arm64 -j "$jobs"
# The arm64 package, its Depends from dpkg-shlibdeps inside the sysroot, installed with apt into
# a fresh Debian 12 arm64 root; its --check and a headless frame there under qemu.
rm -f build/device-arm64/vpe-player_*.deb
(cd build/device-arm64 && cpack >/dev/null)
package_root=$(mktemp -d /tmp/vpe-package-arm64.XXXXXX)
scripts/package-check.sh "$package_root/root" arm64 build/device-arm64/vpe-player_*_arm64.deb
debian_root_remove "$package_root"

test_run_close_stage
echo "all tests passed in $((SECONDS - test_run_started)) s" >&2
