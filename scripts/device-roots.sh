#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Makes the Debian roots the device's checks use, ahead of them: scripts/test.sh runs this in the
# background from its start, while the builds keep the cores busy, since making a root is mostly
# waiting on downloads and unpacking (on a machine whose roots' cache is empty: about 290 s for
# the arm64 sysroot, 230 s for the VM's root, 250 s for the arm64 package check's, docs/ci-budget.md).
#   1. the arm64 sysroot, build/arm64-root (scripts/arm64-sysroot.sh);
#   2. the KMS VM's base root and the arm64 package check's, into the roots' cache only
#      (scripts/lib/root-cache.sh): their checks copy them from there. Each is made of what the
#      device's package needs at run time (scripts/install-deps.sh --list-device-runtime), so it
#      can be made before the package exists. Already cached: nothing to do.
#   scripts/device-roots.sh        (needs root)
set -euo pipefail
cd "$(dirname "$0")/.."
[[ $(id -u) -eq 0 ]] || { echo "device-roots: must run as root (mmdebstrap)" >&2; exit 2; }
scripts/arm64-sysroot.sh
source scripts/lib/debian-root.sh
source scripts/lib/root-cache.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
debian_root_sources "$work"
start=$SECONDS
root_cache_kms_vm_base - ""
root_cache_package_check_base arm64 - ""
echo "device-roots: the VM's and the arm64 package check's base roots ready in $((SECONDS - start)) s" >&2
