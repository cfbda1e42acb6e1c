#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs every test: the suite in a release build, again under AddressSanitizer +
# UndefinedBehaviorSanitizer, the libFuzzer targets briefly (clang), and a device-only
# configure that must succeed without any offline dependency. Installs missing packages.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test

jobs=$(nproc)
step() { printf '\n== %s\n' "$*" >&2; }

step "release build and tests"
cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"

step "ASan + UBSan build and tests"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1 ctest --preset asan -j "$jobs"

step "libFuzzer targets (clang)"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$jobs"
ctest --test-dir build/fuzz --output-on-failure

step "device-only build (proto, renderer, firmware; no offline dependencies)"
cmake --preset device >/dev/null
cmake --build --preset device -j "$jobs"

step "all tests passed"
