#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every test: the suite in a release build, again under AddressSanitizer +
# UndefinedBehaviorSanitizer, the libFuzzer targets briefly (clang), and the device-only build
# (no offline dependency) with its own tests. Installs missing packages. This is what CI runs.
#   scripts/test.sh --quick   a developer's loop: the release build and its tests labelled
#                             unit, gpu or data (not slow; see cmake/VpeTests.cmake), no
#                             sanitizers, fuzzing or device build
# It starts with the style check (scripts/check-format.sh). Every configure is followed by the
# dependency audit (scripts/audit-deps.sh): a file the build found that no package in
# scripts/install-deps.sh brings fails the run, so a package installed by hand on this machine
# cannot hide a broken fresh install.
# CI allows 90 minutes on 2 cores, so the extra builds compile only what they test: the
# sanitizer presets at -O1 -g1 (line tables are enough for the reports; at -O2 -g the ASan
# build took ~15 min, relight_web_encoder.cpp alone 97 s against 27 s), and the fuzz preset
# only its four fuzzers and the rooms they link (46 files, not the whole tree again).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
for argument in "$@"; do
    case "$argument" in
        --quick) quick=1 ;;
        *) echo "test.sh: unknown option $argument (--quick)" >&2; exit 2 ;;
    esac
done
scripts/install-deps.sh --test

jobs=$(nproc)
step() { printf '\n== %s\n' "$*" >&2; }
# configure PRESET: configure with CMake's file API asked for, then audit what it found.
configure() {
    scripts/audit-deps.sh query "build/$1"
    cmake --preset "$1" >/dev/null
    scripts/audit-deps.sh check "build/$1"
}
# audit_headers PRESET: after building, also every system header the compiler read.
audit_headers() { scripts/audit-deps.sh check --headers "build/$1"; }

# Every test must carry a label (cmake/VpeTests.cmake), or the quick path would miss it.
check_labels() {
    local unlabelled
    unlabelled=$(ctest --test-dir "build/$1" -N -LE '^(unit|gpu|slow|data|fuzz)$' | sed -n 's/^ *Test *#[0-9]*: //p')
    if [[ -n "$unlabelled" ]]; then
        echo "test.sh: tests without a label in build/$1 (cmake/VpeTests.cmake):" $unlabelled >&2
        exit 1
    fi
}

step "style (clang-format)"
scripts/check-format.sh

step "release build and tests"
configure release
cmake --build --preset release -j "$jobs"
audit_headers release
check_labels release
if [[ $quick -eq 1 ]]; then
    ctest --preset release -j "$jobs" -LE '^(slow|fuzz)$'
    step "quick tests passed (the full run: scripts/test.sh)"
    exit 0
fi
ctest --preset release -j "$jobs"

step "ASan + UBSan build and tests"
configure asan
cmake --build --preset asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1 ctest --preset asan -j "$jobs"

step "libFuzzer targets (clang)"
configure fuzz
cmake --build --preset fuzz -j "$jobs" --target vpe_fuzzers
ctest --test-dir build/fuzz --output-on-failure

step "device-only build and its tests (proto, renderer, firmware; no offline dependencies)"
configure device
cmake --build --preset device -j "$jobs"
audit_headers device
check_labels device
ctest --test-dir build/device --output-on-failure -j "$jobs"

step "all tests passed"
