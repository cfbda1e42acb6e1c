# SPDX-License-Identifier: MIT
# Shared by the scripts that build Debian 12 roots with mmdebstrap (sourced): the fresh-install
# check, the arm64 sysroot, the package install test. One place knows how to read this
# machine's apt sources and how to remove a root that may still hold bind mounts.

# debian_root_sources WORK: writes this machine's apt sources and its Acquire:: settings into
# WORK (read at run time, so that no host name lives in the repository) and sets $mirror (the
# sources file for mmdebstrap) and $aptopt (the apt options file).
debian_root_sources() {
    local work=$1 sources f
    sources="$work/sources.list"
    : >"$sources"
    [[ -s /etc/apt/sources.list ]] && grep -v '^[[:space:]]*#' /etc/apt/sources.list >>"$sources" || true
    for f in /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
        [[ -f "$f" ]] || continue
        if [[ "$f" == *.sources ]]; then
            # deb822 stanzas: keep them whole and separated by a blank line
            cat "$f" >>"$sources"; echo >>"$sources"
        else
            grep -v '^[[:space:]]*#' "$f" >>"$sources" || true
        fi
    done
    [[ -s "$sources" ]] || { echo "debian-root: this machine has no apt sources" >&2; return 2; }
    # mmdebstrap takes one style at a time: deb822 if any .sources file was read, one-line
    # otherwise.
    if grep -q '^Types:' "$sources"; then
        mirror="$work/sources.sources"
        awk 'BEGIN{RS=""; ORS="\n\n"} /Types:/' "$sources" >"$mirror"
    else
        mirror="$sources"
    fi
    aptopt="$work/apt.conf"
    apt-config dump | grep -E '^Acquire::(Check-Valid-Until|Check-Date|http::Proxy|https::Proxy)' >"$aptopt" || true
}

# A root may hold bind mounts of the host's /dev, /proc, /sys. A run killed with SIGKILL skips
# its trap and leaves them behind; removing such a root naively deletes the host's /dev nodes.
# So every mount under the root is undone first (a stale one included), and the removal never
# crosses into another file system.
debian_root_unmount_below() {
    local m
    awk -v r="$1" '$2 == r || index($2, r "/") == 1 { print $2 }' /proc/self/mounts | sort -r |
        while read -r m; do umount -l "$m" 2>/dev/null || true; done
}
debian_root_remove() {
    debian_root_unmount_below "$1"
    if awk -v r="$1" 'index($2, r "/") == 1 { found = 1 } END { exit !found }' /proc/self/mounts; then
        echo "debian-root: $1 still has mounts; leaving it in place" >&2
        return
    fi
    rm -rf --one-file-system "$1"
}

# debian_root_arm64_binfmt: lets this machine execute aarch64 programs (qemu-user through
# binfmt_misc, with the interpreter opened now: flag F, so it works inside a chroot). Mounts
# binfmt_misc and registers Debian's qemu-aarch64 entry when they are missing. Fails with one
# line when the kernel refuses.
debian_root_arm64_binfmt() {
    local binfmt=/proc/sys/fs/binfmt_misc conf=/usr/lib/binfmt.d/qemu-aarch64.conf
    [[ -f "$conf" ]] || { echo "debian-root: $conf missing (qemu-user-static)" >&2; return 2; }
    if [[ ! -e "$binfmt/register" ]]; then
        mount -t binfmt_misc binfmt_misc "$binfmt" 2>/dev/null ||
            { echo "debian-root: cannot mount binfmt_misc on $binfmt: aarch64 programs cannot run here" >&2; return 2; }
    fi
    if [[ ! -e "$binfmt/qemu-aarch64" ]]; then
        cat "$conf" >"$binfmt/register" 2>/dev/null ||
            { echo "debian-root: the kernel refused qemu-aarch64 in $binfmt/register" >&2; return 2; }
    fi
}
