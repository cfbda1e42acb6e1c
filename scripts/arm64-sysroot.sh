#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Makes the arm64 sysroot the device is cross-built against and its tests run in: a Debian 12
# arm64 root holding exactly `scripts/install-deps.sh --list-arm64-root` (the device's
# libraries, its test frameworks, Mesa), installed by mmdebstrap with its maintainer scripts
# run under qemu-user. Nothing arm64 is installed on this machine itself, so the amd64 build
# and the arm64 one cannot see each other's libraries, and a library the device build takes
# from the offline set fails to link instead of passing unnoticed.
#
#   scripts/arm64-sysroot.sh [ROOT]     (default build/arm64-root; rebuilt only when the
#                                        package list changes; needs root)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/debian-root.sh
root=$(realpath -m "${1:-build/arm64-root}")
[[ $(id -u) -eq 0 ]] || { echo "arm64-sysroot: must run as root (mmdebstrap, binfmt_misc)" >&2; exit 2; }
scripts/install-deps.sh --arm64 >/dev/null
debian_root_arm64_binfmt

mapfile -t packages < <(scripts/install-deps.sh --list-arm64-root)
stamp="$root/.vpe-packages"
wanted=$(printf '%s\n' "${packages[@]}")
if [[ -f "$stamp" && "$(cat "$stamp")" == "$wanted" ]]; then
    echo "arm64-sysroot: $root is up to date" >&2
    exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
debian_root_sources "$work"
[[ -e "$root" ]] && debian_root_remove "$root"
building="$root.building"
[[ -e "$building" ]] && debian_root_remove "$building"
# test.sh starts this before anything is built, so on a fresh clone build/ does not exist yet.
mkdir -p "$(dirname "$root")"
start=$(date +%s)
# Made once per state of Debian's archive and package list (scripts/lib/root-cache.sh), then
# copied into each clone's build folder.
source scripts/lib/root-cache.sh
key=$(root_cache_key "$mirror" arm64-sysroot arm64 essential "${packages[@]}") ||
    echo "arm64-sysroot: Debian's archive state unreadable; making the root without the cache" >&2
if root_cache_restore arm64-sysroot "$key" "$building"; then
    echo "arm64-sysroot: copied from the cache ($(root_cache_dir))" >&2
else
    echo "arm64-sysroot: building a Debian 12 arm64 root in $root (${#packages[@]} packages)" >&2
    # essential: dpkg and its database (the dependency audit asks it who owns a header), no apt.
    if ! mmdebstrap --arch=arm64 --variant=essential --include="$(IFS=,; echo "${packages[*]}")" \
        --aptopt="$aptopt" --format=directory bookworm "$building" "$mirror" >"$work/mmdebstrap.log" 2>&1; then
        tail -n 20 "$work/mmdebstrap.log" >&2
        echo "arm64-sysroot: mmdebstrap failed (its log's end above)" >&2
        debian_root_remove "$building"
        exit 1
    fi
    debian_root_unmount_below "$building"
    root_cache_store arm64-sysroot "$key" "$building"
fi
printf '%s\n' "$wanted" >"$building/.vpe-packages"
mv "$building" "$root"
echo "arm64-sysroot: ready in $(($(date +%s) - start)) s, $(du -sh "$root" | cut -f1)" >&2
