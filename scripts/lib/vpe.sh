# SPDX-License-Identifier: MIT
# Shared by the scripts (sourced from the repository root): build the vpe command and read
# numbers from its --json reports.

# Builds `vpe` in the release preset and sets $vpe to its absolute path.
build_vpe() {
    cmake --preset release >/dev/null
    cmake --build --preset release --target vpe -j "$(nproc)"
    vpe=$(realpath build/release/offline/vpe)
}

# json_field NAME < REPORT: the last numeric value of "NAME": in a JSON report.
json_field() {
    sed -n "s/.*\"$1\":\([0-9.eE+-]*\).*/\1/p" | tail -1
}
