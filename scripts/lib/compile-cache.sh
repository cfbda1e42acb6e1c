# SPDX-License-Identifier: MIT
# The compile cache's one definition (sourced): scripts/test.sh builds through it, and
# scripts/check-fresh-debian.sh bind-mounts its folder into the fresh root. Every build compiles
# through ccache, and the cache lives outside the clone ($VPE_CCACHE_DIR, else
# ~/.cache/vpe/ccache), so a run compiles only what changed since the last build of any clone
# on this machine: CI runs in a fresh clone on the machine of the session that just built the
# same tree. Keys that cannot go stale (tests/scripts/compile_cache_test.sh proves each):
#   - depend mode: the key hashes the source, the compiler's arguments and the contents of every
#     header the compile read (ninja's dependency files list them, system headers included), so
#     a changed header is a miss, and a missing header or package a miss whose compile fails;
#   - the compiler by its contents, not its time stamp: a fresh root's g++ from the same Debian
#     package hits, another version misses;
#   - paths relative to the repository and the build folder's name left out, so every clone
#     shares one cache; each preset's own flags (sanitizers, clang, the arm64 cross compiler
#     and its sysroot) are part of its keys;
#   - precompiled headers: the .gch is hashed like any header it reads (pch_defines: GCC's own
#     rule that a precompiled header matches its defines; time_macros: no source reads
#     __DATE__ or __TIME__).
# The release build and the device package's build share objects: the package's sources are
# compiled exactly as the release build compiled them.

# compile_cache_use REPOSITORY: exports ccache's settings and CMake's launchers for builds of
# REPOSITORY.
compile_cache_use() {
    export CCACHE_DIR="${VPE_CCACHE_DIR:-${XDG_CACHE_HOME:-${HOME:-/root}/.cache}/vpe/ccache}" \
        CCACHE_BASEDIR="$1" CCACHE_NOHASHDIR=true CCACHE_DEPEND=true \
        CCACHE_COMPILERCHECK=content CCACHE_SLOPPINESS=pch_defines,time_macros \
        CCACHE_MAXSIZE=${VPE_CCACHE_SIZE:-24G} \
        CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
    mkdir -p "$CCACHE_DIR"
}
