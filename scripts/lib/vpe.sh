# SPDX-License-Identifier: MIT
# Shared by the scripts (sourced from the repository root): build the vpe command and read
# numbers from its --json reports.

# Builds `vpe` and `vpe-player` in the release preset and sets $vpe and $player to their
# absolute paths.
build_vpe() {
    # Through this machine's compile cache (scripts/lib/compile-cache.sh), as scripts/test.sh
    # builds: a demo after the tests, or the tests after a demo, compiles nothing twice.
    if command -v ccache >/dev/null; then
        source scripts/lib/compile-cache.sh
        compile_cache_use "$PWD"
    fi
    cmake --preset release >/dev/null
    cmake --build --preset release --target vpe vpe-player -j "$(nproc)"
    vpe=$(realpath build/release/offline/vpe)
    player=$(realpath build/release/firmware/player/vpe-player)
}

# json_field NAME < REPORT: the last numeric value of "NAME": in a JSON report.
json_field() {
    sed -n "s/.*\"$1\": *\([0-9.eE+-]*\).*/\1/p" | tail -1
}
