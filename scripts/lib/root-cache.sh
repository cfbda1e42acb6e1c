# SPDX-License-Identifier: MIT
# The Debian roots' cache (sourced, after scripts/lib/debian-root.sh): the arm64 sysroot, the
# package check's base root and the KMS VM's base root are made by mmdebstrap once per state of
# Debian's archive, not once per clone, the way scripts/lib/compile-cache.sh keeps objects.
# Making them took about 370 s of each CI run (the arm64 sysroot ~200 s beside the builds, the
# arm64 package's root ~130 s, the VM's ~90 s), nearly all of it downloading, unpacking and
# running maintainer scripts under qemu-user, for roots that come out the same every time.
#
# What a cached root holds is Debian's alone: vpe's package is never in it. Each run installs
# the package with apt into a fresh copy of the base root, so the package's install, its
# maintainer scripts and its Depends are tested every run exactly as before.
#
# A key cannot go stale: it hashes what the root is made of (architecture, variant, the package
# list, the maker's version below) and the archive's state, the InRelease file of every suite in
# this machine's apt sources: when Debian publishes anything (a point release, a security fix),
# the InRelease changes and the root is made again. When the archive cannot be read the root is
# made afresh and not cached. The cache lives in $VPE_ROOT_CACHE_DIR, else
# ~/.cache/vpe/roots; one root is kept per name, the newest.

# Changes when the way a cached root is made changes (mmdebstrap's options in the callers).
root_cache_maker_version=1

root_cache_dir() { echo "${VPE_ROOT_CACHE_DIR:-${XDG_CACHE_HOME:-${HOME:-/root}/.cache}/vpe/roots}"; }

# root_cache_archive_state SOURCES: prints one hash of the InRelease file of every suite that
# SOURCES (a one-line or deb822 sources file, from debian_root_sources) names. Fails when one
# cannot be read.
root_cache_archive_state() {
    python3 - "$1" <<'EOF'
import hashlib, sys, urllib.request
text = open(sys.argv[1]).read()
suites = []
if "Types:" in text:
    for stanza in text.split("\n\n"):
        fields = dict(l.split(":", 1) for l in stanza.splitlines() if ":" in l and not l.startswith(("#", " ")))
        for uri in fields.get("URIs", "").split():
            suites += [(uri, s) for s in fields.get("Suites", "").split()]
else:
    for line in text.splitlines():
        words = [w for w in line.split() if not w.startswith("[") and not w.endswith("]")]
        if len(words) >= 3 and words[0] == "deb":
            suites.append((words[1], words[2]))
if not suites:
    sys.exit("root-cache: no suite in " + sys.argv[1])
state = hashlib.sha256()
for uri, suite in sorted(set(suites)):
    url = uri.rstrip("/") + "/dists/" + suite + "/InRelease"
    with urllib.request.urlopen(url, timeout=30) as response:
        state.update(url.encode() + b"\n" + hashlib.sha256(response.read()).digest())
print(state.hexdigest())
EOF
}

# root_cache_key SOURCES WORDS...: the key of a root made from SOURCES by WORDS (whatever
# defines it: architecture, variant, packages). Fails when the archive cannot be read.
# A run that makes roots at different times (scripts/test.sh: in the background at its start, and
# in its stages) sets $VPE_ROOT_ARCHIVE_STATE once (root_cache_archive_state) so that its keys
# agree: Debian publishes several times a day, and a root made at the start then missed at the
# end was made twice (the cold run of 0892509: 180 s).
root_cache_key() {
    local sources=$1 state=${VPE_ROOT_ARCHIVE_STATE:-}
    shift
    [[ -n "$state" ]] || state=$(root_cache_archive_state "$sources") || return 1
    printf '%s\n' "maker $root_cache_maker_version" "archive $state" "$@" | sha256sum | cut -c1-24
}

# root_cache_note WHAT NAME: one line for scripts/test.sh's report, when it asks for them
# ($VPE_ROOT_CACHE_LOG).
root_cache_note() {
    [[ -z "${VPE_ROOT_CACHE_LOG:-}" ]] || echo "$1 $2" >>"$VPE_ROOT_CACHE_LOG"
}

# root_cache_restore NAME KEY ROOT: copies the cached root NAME with KEY to ROOT (absent).
# Fails, leaving ROOT absent, when there is none.
root_cache_restore() {
    local cached
    cached="$(root_cache_dir)/$1-$2"
    [[ -n "$2" && -f "$cached/.vpe-root-complete" ]] || return 1
    cp -a --reflink=auto "$cached" "$3"
    rm -f "$3/.vpe-root-complete"
    root_cache_note restored "$1"
}

# root_cache_store NAME KEY ROOT: keeps a copy of ROOT (no mounts left in it) as NAME with KEY,
# replacing older roots of that NAME. Only a whole copy is ever seen under its final name.
root_cache_store() {
    local dir name=$1 key=$2 root=$3 partial old
    root_cache_note made "$name"
    [[ -n "$key" ]] || return 0
    dir=$(root_cache_dir)
    mkdir -p "$dir"
    partial="$dir/.$name-$key.partial.$$"
    rm -rf --one-file-system "$partial"
    cp -a --reflink=auto "$root" "$partial"
    touch "$partial/.vpe-root-complete"
    for old in "$dir/$name"-*; do
        [[ -e "$old" && "$old" != "$dir/$name-$key" ]] && rm -rf --one-file-system "$old"
    done
    rm -rf --one-file-system "$dir/$name-$key"
    mv "$partial" "$dir/$name-$key"
}

# root_cache_chroot ROOT COMMAND...: runs COMMAND in ROOT with /proc, /sys and /dev mounted, as
# mmdebstrap's hooks have them; the mounts are undone however COMMAND ends.
root_cache_chroot() {
    local root=$1 status=0
    shift
    mount -t proc proc "$root/proc"
    mount -t sysfs sysfs "$root/sys"
    mount --rbind /dev "$root/dev"
    mount --make-rslave "$root/dev"
    chroot "$root" "$@" || status=$?
    debian_root_unmount_below "$root"
    return $status
}

# root_cache_depends DEB: the packages DEB's Depends names, one per line, without versions (the
# first of alternatives, as apt chooses): what a base root for DEB includes.
root_cache_depends() {
    dpkg-deb -f "$1" Depends | tr ',' '\n' | sed 's/|.*//; s/(.*)//; s/:any//; s/[[:space:]]//g' |
        grep . | sort -u
}

# root_cache_device_base NAME ARCH ROOT DEB [PACKAGE...] [-- MMDEBSTRAP_OPTION...]: makes ROOT
# (absent) a Debian 12 root of ARCH, variant apt, holding what vpe-player's package needs at run
# time (scripts/install-deps.sh --list-device-runtime), the Depends of the package file DEB when
# DEB is not empty, and the PACKAGEs. A Depends the list lacks is taken in too; the key then
# differs from the one scripts/device-roots.sh made ahead, so the root is made here, later and
# slower, but right. From the cache NAME when it holds the key, else made by mmdebstrap (its
# output on stderr) and kept there. ROOT "-" only makes sure the cache holds it. Uses $mirror and
# $aptopt (debian_root_sources).
root_cache_device_base() {
    local name=$1 arch=$2 root=$3 deb=$4 include key status=0 scratch=""
    shift 4
    local packages=() options=()
    while [[ $# -gt 0 && $1 != -- ]]; do packages+=("$1"); shift; done
    [[ $# -gt 0 ]] && shift
    options=("$@")
    mapfile -t packages < <({
        printf '%s\n' "${packages[@]}"
        scripts/install-deps.sh --list-device-runtime
        [[ -z "$deb" ]] || root_cache_depends "$deb"
    } | grep . | sort -u)
    include=$(IFS=,; echo "${packages[*]}")
    key=$(root_cache_key "$mirror" "$name" "$arch" apt "$include" "${options[@]}") ||
        echo "root-cache: Debian's archive state unreadable; $name made without the cache" >&2
    if [[ "$root" == - ]]; then
        [[ -n "$key" && -f "$(root_cache_dir)/$name-$key/.vpe-root-complete" ]] && return 0
        scratch=$(mktemp -d "/tmp/vpe-$name.XXXXXX")
        root="$scratch/root"
    elif root_cache_restore "$name" "$key" "$root"; then
        echo "root-cache: $name from the cache ($include)" >&2
        return 0
    fi
    echo "root-cache: making $name with mmdebstrap ($include)" >&2
    rm -rf --one-file-system "$root"
    mmdebstrap --variant=apt --architectures="$arch" --aptopt="$aptopt" --format=directory \
        --include="$include" "${options[@]}" bookworm "$root" "$mirror" >&2 || status=$?
    debian_root_unmount_below "$root"
    if [[ $status -eq 0 ]]; then
        root_cache_store "$name" "$key" "$root"
    else
        echo "root-cache: mmdebstrap failed making $name (exit $status)" >&2
    fi
    [[ -z "$scratch" ]] || debian_root_remove "$scratch"
    return $status
}

# The two base roots the device's package is installed into, defined once for their checks and
# for scripts/device-roots.sh, which makes them ahead. ROOT and DEB as root_cache_device_base's.
# root_cache_package_check_base ARCH ROOT DEB: scripts/package-check.sh's root.
root_cache_package_check_base() { root_cache_device_base "package-check-$1" "$1" "$2" "$3"; }
# root_cache_kms_vm_base ROOT DEB: scripts/kms-vm-check.sh's guest, amd64, which boots: the kernel
# and systemd too; no documentation, manual pages or translations (a smaller disk image).
root_cache_kms_vm_base() {
    root_cache_device_base kms-vm amd64 "$1" "$2" systemd-sysv udev kmod linux-image-amd64 -- \
        --dpkgopt='path-exclude=/usr/share/doc/*' --dpkgopt='path-exclude=/usr/share/man/*' \
        --dpkgopt='path-exclude=/usr/share/locale/*'
}
