#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The dependency audit (scripts/audit-deps.sh) on this very build: it passes with the packages
# scripts/install-deps.sh names, and fails, naming the package config, when one is dropped.
#   audit_deps_test.sh SOURCE_DIR BUILD_DIR passes|drop PACKAGE EXPECTED_FILE
# Exits 77 (SKIP) without CMake's file-API reply (configure after 'audit-deps.sh query'), jq or dpkg.
set -euo pipefail
source_dir=$1 build=$2 mode=$3
audit="$source_dir/scripts/audit-deps.sh"
command -v jq >/dev/null && command -v dpkg >/dev/null ||
    { echo "SKIP: jq or dpkg missing"; exit 77; }
ls "$build"/.cmake/api/v1/reply/index-*.json >/dev/null 2>&1 ||
    { echo "SKIP: $build was configured without the audit's file-API query"; exit 77; }

case "$mode" in
    passes)
        "$audit" check "$build"
        ;;
    drop)
        package=$4 expected=$5
        named=$(mktemp)
        trap 'rm -f "$named"' EXIT
        "$source_dir/scripts/install-deps.sh" --list --test | grep -vxF "$package" >"$named"
        if output=$("$audit" check --named "$named" "$build" 2>&1); then
            echo "FAIL: the audit passed without $package: $output"; exit 1
        fi
        echo "$output"
        grep -q "$expected.* ← $package" <<<"$output" ||
            { echo "FAIL: expected a line naming $expected ← $package"; exit 1; }
        ;;
    *) echo "unknown mode $mode"; exit 2 ;;
esac
