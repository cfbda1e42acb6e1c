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
status=0
while IFS= read -r -d '' file; do
    if ! clang-format --dry-run --Werror "$file" >/dev/null 2>&1; then
        echo "check-format: $file is not clang-formatted (clang-format -i $file)" >&2
        status=1
    fi
done < <(git ls-files -z -- '*.cpp' '*.h')
exit $status
