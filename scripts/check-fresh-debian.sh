#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Proves that the README's two commands work on a truly fresh Debian 12: builds a minimal root
# with mmdebstrap from this machine's own apt configuration, clones the current commit into it
# (with ../shared beside it, read-only, when present) and runs exactly the README's commands
# there. CI runs on a machine where packages may have been installed by hand; this cannot.
#
#   scripts/check-fresh-debian.sh [--keep] [--only demo|test] [WORKDIR]
#
# Needs root (mmdebstrap, chroot, bind mounts); installs mmdebstrap if it is missing.
# Uncommitted changes are not part of the check: it clones HEAD.
set -euo pipefail
cd "$(dirname "$0")/.."
top=$(pwd)

keep=0
only=""
work=""
while [[ $# -gt 0 ]]; do
    case "$1" in
        --keep) keep=1 ;;
        --only) only=$2; shift ;;
        -h|--help) sed -n '3,11p' "$0"; exit 0 ;;
        -*) echo "check-fresh-debian: unknown option $1" >&2; exit 2 ;;
        *) work=$1 ;;
    esac
    shift
done
[[ -z "$only" || "$only" == demo || "$only" == test ]] ||
    { echo "check-fresh-debian: --only takes demo or test, not '$only'" >&2; exit 2; }
[[ $(id -u) -eq 0 ]] || { echo "check-fresh-debian: must run as root (mmdebstrap, chroot)" >&2; exit 2; }
command -v mmdebstrap >/dev/null ||
    { DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends mmdebstrap >/dev/null; }

# The README's commands: the lines of its first ```sh block, comments dropped.
mapfile -t commands < <(awk '/^```sh/{inside=1; next} inside && /^```/{exit} inside' README.md |
    sed 's/[[:space:]]*#.*$//' | sed '/^[[:space:]]*$/d')
[[ ${#commands[@]} -eq 2 ]] ||
    { echo "check-fresh-debian: README.md: expected two commands in its first sh block, found ${#commands[@]}" >&2; exit 2; }
names=(demo test)

work=${work:-$(mktemp -d /tmp/vpe-fresh.XXXXXX)}
mkdir -p "$work"
root="$work/root"
commit=$(git rev-parse HEAD)

# This machine's apt sources (scripts/lib/debian-root.sh); the root's removal undoes its bind
# mounts first.
source scripts/lib/debian-root.sh
debian_root_sources "$work"
remove_root() { debian_root_remove "$root"; }
cleanup() { if [[ $keep -eq 0 ]]; then remove_root; else debian_root_unmount_below "$root"; fi; }
[[ -e "$root" ]] && remove_root
trap cleanup EXIT

echo "check-fresh-debian: building a Debian 12 root in $root" >&2
start=$(date +%s)
mmdebstrap --variant=apt --include=git,ca-certificates --aptopt="$aptopt" \
    --format=directory bookworm "$root" "$mirror" >"$work/mmdebstrap.log" 2>&1 ||
    { echo "check-fresh-debian: mmdebstrap failed (see $work/mmdebstrap.log)" >&2; exit 1; }
echo "check-fresh-debian: root ready in $(($(date +%s) - start)) s" >&2

mkdir -p "$root/work"
git clone -q --no-local "$top" "$root/work/main"
git -C "$root/work/main" checkout -q "$commit"
if [[ -d "$top/../shared" ]]; then
    mkdir -p "$root/work/shared"
    mount --bind "$top/../shared" "$root/work/shared"
    mount -o remount,bind,ro "$root/work/shared"
fi
# This machine's compile cache (scripts/lib/compile-cache.sh), where the root's HOME keeps it:
# the fresh root compiles only what no build here compiled, with keys that hash every header
# it reads, so a package missing from the root still fails its compile.
source scripts/lib/compile-cache.sh
compile_cache_use "$top"
mkdir -p "$root/root/.cache/vpe/ccache"
mount --bind "$CCACHE_DIR" "$root/root/.cache/vpe/ccache"
# And its cache of Debian roots (scripts/lib/root-cache.sh): they hold Debian's packages only,
# keyed by the archive's state; vpe's package is installed into a fresh copy each run.
source scripts/lib/root-cache.sh
mkdir -p "$(root_cache_dir)" "$root/root/.cache/vpe/roots"
mount --bind "$(root_cache_dir)" "$root/root/.cache/vpe/roots"
for fs in proc sys dev dev/pts; do
    mkdir -p "$root/$fs"
    mount --bind "/$fs" "$root/$fs"
done
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
# A Debian 12 installation has /etc/hosts (the installer writes it; no package does), and
# "localhost" resolves there: selenium's chromedriver service waits on localhost:PORT and the
# control page's test never started in a root made without it.
[[ -e "$root/etc/hosts" ]] || printf '127.0.0.1\tlocalhost\n::1\t\tlocalhost ip6-localhost ip6-loopback\n' >"$root/etc/hosts"
# This machine's own certificate authorities (/usr/local/share/ca-certificates: a network that
# inspects TLS, say), as its apt settings above: a fresh machine on that network is given them
# too, or HTTPS (the build's download of the control page's MQTT client) fails where it would
# not on the open internet.
if compgen -G "/usr/local/share/ca-certificates/*.crt" >/dev/null; then
    mkdir -p "$root/usr/local/share/ca-certificates"
    cp /usr/local/share/ca-certificates/*.crt "$root/usr/local/share/ca-certificates/"
    chroot "$root" update-ca-certificates >/dev/null 2>&1 ||
        echo "check-fresh-debian: update-ca-certificates failed in the root" >&2
fi

status=0
for i in 0 1; do
    [[ -n "$only" && "$only" != "${names[i]}" ]] && continue
    log="$work/${names[i]}.log"
    echo "check-fresh-debian: running '${commands[i]}' (log: $log)" >&2
    begin=$(date +%s)
    set +e
    chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        LANG=C.UTF-8 bash -c "cd /work/main && ${commands[i]}" >"$log" 2>&1
    rc=$?
    set -e
    seconds=$(($(date +%s) - begin))
    last=$(grep -v '^[[:space:]]*$' "$log" | tail -n 1)
    printf '%s: %s → exit %d in %d s; last line: %s\n' "${names[i]}" "${commands[i]}" "$rc" "$seconds" "$last"
    [[ $rc -eq 0 ]] || status=1
done
echo "commit $commit, Debian $(cat "$root/etc/debian_version")"
exit $status
