#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Fails, one line per file, when a tracked C++ source or header is not as clang-format (the
# root .clang-format) would write it. scripts/test.sh runs it first; fix with
#   clang-format -i FILE
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format >/dev/null; then
    echo "check-format: clang-format is missing (scripts/install-deps.sh --test installs it)" >&2
    exit 2
fi
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    echo "check-format: $(pwd) is not a git checkout; nothing to list" >&2
    exit 2
fi
# Files in batches, as many batches at once as there are cores (one clang-format per file, one
# after another, took 76 s of CI's run); a batch that fails is checked again file by file, to
# name each file.
export LC_ALL=C
git ls-files -z -- '*.cpp' '*.h' | xargs -0 -r -P "$(nproc)" -n 32 sh -c '
    clang-format --dry-run --Werror "$@" >/dev/null 2>&1 && exit 0
    for file; do
        clang-format --dry-run --Werror "$file" >/dev/null 2>&1 ||
            echo "check-format: $file is not clang-formatted (clang-format -i $file)" >&2
    done
    exit 1' check-format ||
    exit 1
