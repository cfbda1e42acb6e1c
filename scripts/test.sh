#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every test: the suite in a release build, again under AddressSanitizer +
# UndefinedBehaviorSanitizer, the libFuzzer targets briefly (clang), and a device-only
# configure that must succeed without any offline dependency. Installs missing packages.
# Every configure is followed by the dependency audit (scripts/audit-deps.sh): a file the
# build found that no package in scripts/install-deps.sh brings fails the run, so a package
# installed by hand on this machine cannot hide a broken fresh install.
set -euo pipefail
cd "$(dirname "$0")/.."
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

step "release build and tests"
configure release
cmake --build --preset release -j "$jobs"
audit_headers release
ctest --preset release -j "$jobs"

step "ASan + UBSan build and tests"
configure asan
cmake --build --preset asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1 ctest --preset asan -j "$jobs"

step "libFuzzer targets (clang)"
configure fuzz
cmake --build --preset fuzz -j "$jobs"
ctest --test-dir build/fuzz --output-on-failure

step "device-only build (proto, renderer, firmware; no offline dependencies)"
configure device
cmake --build --preset device -j "$jobs"
audit_headers device

step "all tests passed"
