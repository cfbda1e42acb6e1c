#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The compile cache's keys (scripts/lib/compile-cache.sh), with the real ccache and compiler, in
# a cache of its own: a compile hits from another clone, and a changed package header misses; a
# removed one is never hidden by a hit (the compile runs and fails, as in a fresh root without
# the package).
#   compile_cache_test.sh SOURCE_DIR
# Exits 77 (skipped) when ccache is absent.
set -euo pipefail
source_dir=$1
command -v ccache >/dev/null || { echo "compile_cache_test: ccache is not installed; skipped"; exit 77; }
compiler=${CXX:-g++}

work=$(mktemp -d /tmp/vpe-compile-cache-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
export VPE_CCACHE_DIR="$work/cache"
source "$source_dir/scripts/lib/compile-cache.sh"

# A "package" header under a system include folder, and two clones of one source.
mkdir -p "$work/usr/include" "$work/clone-a" "$work/clone-b"
echo 'inline int packageValue() { return 1; }' >"$work/usr/include/vpe_probe_package.h"
for clone in clone-a clone-b; do
    printf '#include <vpe_probe_package.h>\nint value() { return packageValue(); }\n' \
        >"$work/$clone/value.cpp"
done

counts() {
    ccache --print-stats | awk '$1 ~ /^(direct|preprocessed)_cache_hit$/ { h += $2 }
        $1 == "cache_miss" { m += $2 } END { print h + 0, m + 0 }'
}
# compile CLONE: as ninja compiles, from the clone's build folder, with a dependency file.
compile() {
    compile_cache_use "$work/$1"
    mkdir -p "$work/$1/build"
    (cd "$work/$1/build" && ccache "$compiler" -isystem "$work/usr/include" -O1 -MD \
        -MF value.o.d -c ../value.cpp -o value.o)
}
expect() {
    local label=$1 hits=$2 misses=$3 got
    got=$(counts)
    [[ "$got" == "$hits $misses" ]] ||
        { echo "compile_cache_test: $label: expected $hits hits and $misses misses, got $got" >&2; exit 1; }
    echo "compile_cache_test: $label: $got (hits misses), as expected"
}

compile clone-a
expect "first compile" 0 1
compile clone-b
expect "the same source in another clone" 1 1
grep -q vpe_probe_package.h "$work/clone-b/build/value.o.d" ||
    { echo "compile_cache_test: a hit's dependency file lost the package header (the audit reads it)" >&2; exit 1; }
echo 'inline int packageValue() { return 2; }' >"$work/usr/include/vpe_probe_package.h"
compile clone-a
expect "the package header changed" 1 2
rm "$work/usr/include/vpe_probe_package.h"
if compile clone-b 2>"$work/error.txt"; then
    echo "compile_cache_test: the package header is gone, yet the compile succeeded (a cache hit hid it)" >&2
    exit 1
fi
grep -q 'vpe_probe_package.h' "$work/error.txt" ||
    { echo "compile_cache_test: the failed compile does not name the missing header:" >&2; cat "$work/error.txt" >&2; exit 1; }
expect "the package header removed (no hit)" 1 2
echo "compile_cache_test: passed"
