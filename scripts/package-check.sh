#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The device package's install test (docs/device-package.md): checks what
# vpe-player_<version>_<ARCH>.deb holds (dpkg-deb -c / -I: the player, the board files, the
# systemd unit with its watchdog and the package's paths, the example bundles, Depends from
# dpkg-shlibdeps), then installs it into a fresh Debian 12 root (a copy of a base root that
# mmdebstrap made from Debian, scripts/lib/root-cache.sh) with
# `apt-get install ./vpe-player_*.deb` (dependencies from Debian) and runs, in that root,
# `vpe-player --board /usr/share/vpe/boards/headless.toml --check` and one headless frame of the
# example bundle. Prints one JSON line; exit status 0 when every check passed, 1 when one
# failed, 2 on bad arguments.
#   scripts/package-check.sh ROOTDIR [ARCH [DEB]]
#   scripts/package-check.sh --contents-only [ARCH [DEB]]   the package's checks alone (1 s,
#                                                           no root, no network)
# ROOTDIR: where the root is made (absent or empty; kept afterwards, remove it as root with
# rm -rf --one-file-system). ARCH: the Debian architecture (default: this machine's); another
# one runs through qemu-user (binfmt_misc, qemu-user-static). DEB: default
# build/device/vpe-player_*_ARCH.deb (`cpack` in build/device).
# Needs root (mmdebstrap, chroot) and Debian's mirrors. About 20 s for amd64 here.
set -euo pipefail
cd "$(dirname "$0")/.."

fail_usage() { echo "package-check: $1" >&2; exit 2; }
[[ $# -ge 1 && $# -le 3 ]] ||
    fail_usage "usage: scripts/package-check.sh ROOTDIR|--contents-only [ARCH [DEB]]"
root=$1
contents_only=0
[[ "$root" == --contents-only ]] && contents_only=1
[[ $contents_only -eq 1 || "$root" != -* ]] || fail_usage "$root: unknown option"
arch=${2:-$(dpkg --print-architecture)}
[[ "$arch" =~ ^[a-z0-9]+$ ]] || fail_usage "ARCH: expected a Debian architecture such as amd64 or arm64, got \"$arch\""
if [[ $# -ge 3 ]]; then
    deb=$3
else
    shopt -s nullglob
    debs=(build/device/vpe-player_*_"$arch".deb)
    shopt -u nullglob
    [[ ${#debs[@]} -eq 1 ]] ||
        fail_usage "DEB: expected one build/device/vpe-player_*_$arch.deb (run cpack in build/device), found ${#debs[@]}"
    deb=${debs[0]}
fi
[[ -f "$deb" ]] || fail_usage "DEB: $deb: no such file"
deb=$(realpath "$deb")
if [[ $contents_only -eq 0 ]]; then
    [[ $(id -u) -eq 0 ]] || fail_usage "must run as root (mmdebstrap, chroot)"
    if [[ -e "$root" ]] && [[ -n "$(ls -A "$root" 2>/dev/null)" ]]; then
        fail_usage "ROOTDIR: $root exists and is not empty"
    fi
    command -v mmdebstrap >/dev/null || fail_usage "mmdebstrap is missing (scripts/install-deps.sh --test)"
    if [[ "$arch" != "$(dpkg --print-architecture)" ]]; then
        source scripts/lib/debian-root.sh
        if [[ "$arch" == arm64 ]]; then
            debian_root_arm64_binfmt || exit 2
        fi
    fi
fi

start=$(date +%s.%N)
work=$(mktemp -d /tmp/vpe-package-check.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=()
check() {  # check NAME COMMAND...: records NAME as failed when COMMAND fails
    local name=$1
    shift
    if ! "$@"; then
        failures+=("$name")
        echo "package-check: FAILED: $name" >&2
    fi
}

# 1. The package's contents and control fields.
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$work/contents"
dpkg-deb -f "$deb" Package Version Architecture Depends >"$work/control"
for path in /usr/bin/vpe-player /usr/share/vpe/boards/headless.toml /usr/share/vpe/boards/rpi4.toml \
    /usr/share/vpe/boards/rpi5.toml /usr/lib/systemd/system/vpe-player.service \
    /usr/share/vpe/examples/vase-640x360.vpeb /usr/share/vpe/examples/vase-1920x1080.vpeb; do
    check "contents: $path" grep -qx "$path" "$work/contents"
done
depends=$(dpkg-deb -f "$deb" Depends)
for dependency in libegl1 libgbm1 libgles2 libdrm2 libgl1-mesa-dri adduser; do
    check "Depends: $dependency" grep -qE "(^|, )$dependency( |,|$)" <<<"$depends"
done
check "Architecture: $arch" test "$(dpkg-deb -f "$deb" Architecture)" = "$arch"
dpkg-deb --ctrl-tarfile "$deb" | tar -t >"$work/control-files"
for script in postinst prerm postrm; do
    check "control: $script" grep -qx "./$script" "$work/control-files"
done
dpkg-deb --fsys-tarfile "$deb" | tar -xO ./usr/lib/systemd/system/vpe-player.service >"$work/unit"
check "unit: ExecStart in /usr/bin" grep -qx \
    'ExecStart=/usr/bin/vpe-player --board /etc/vpe/board.toml --bundle /var/lib/vpe/scene.vpeb' "$work/unit"
check "unit: WatchdogSec" grep -qx 'WatchdogSec=10' "$work/unit"
check "unit: no template placeholder left" test "$(grep -c '@' "$work/unit")" = 0

if [[ $contents_only -eq 1 ]]; then
    python3 -c 'import json, sys; print(json.dumps({"package": sys.argv[1], "arch": sys.argv[2], "depends": sys.argv[3], "files": int(sys.argv[4]), "status": "ok" if sys.argv[5] == "" else "failed", "failed": [f for f in sys.argv[5].split("|") if f]}))' \
        "$(basename "$deb")" "$arch" "$depends" "$(grep -c . "$work/contents")" "$(IFS='|'; echo "${failures[*]+"${failures[*]}"}")"
    [[ ${#failures[@]} -eq 0 ]]
    exit
fi

# 2. A fresh Debian 12 root (essential + apt), the package installed from its file with apt,
# and the player run inside it. The root starts as a copy of a base root holding the packages
# the package's Depends names, made by mmdebstrap from Debian once per state of the archive
# (root_cache_device_base in scripts/lib/root-cache.sh; scripts/device-roots.sh makes it ahead):
# apt still checks every Depends, versions included, against what Debian shipped, and the
# package's own install and maintainer scripts run every time.
source scripts/lib/debian-root.sh
source scripts/lib/root-cache.sh
debian_root_sources "$work" || exit 2
cp "$deb" "$work/"
name=$(basename "$deb")
root=$(realpath -m "$root")
rmdir "$root" 2>/dev/null || true  # absent or empty, checked above
mkdir -p "$(dirname "$root")"
if ! root_cache_package_check_base "$arch" "$root" "$work/$name" 2>"$work/mmdebstrap.log"; then
    tail -n 20 "$work/mmdebstrap.log" >&2
    echo "package-check: the base root could not be made (its log's end above)" >&2
    exit 1
fi
cp "$work/$name" "$root/tmp/"
if ! root_cache_chroot "$root" sh -c "cd /tmp && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ./$name" \
    >"$work/install.log" 2>&1; then
    tail -n 20 "$work/install.log" >&2
    echo "package-check: apt-get install ./$name failed" >&2
    exit 1
fi
in_root() { root_cache_chroot "$root" "$@"; }
status=0
in_root vpe-player --board /usr/share/vpe/boards/headless.toml --check >"$work/check.txt" 2>&1 || status=$?
echo $status >"$work/check.status"
status=0
in_root vpe-player --board /usr/share/vpe/boards/headless.toml --bundle /usr/share/vpe/examples/vase-640x360.vpeb \
    --frames 1 --out /tmp/frame --json >"$work/frame.txt" 2>&1 || status=$?
echo $status >"$work/frame.status"
cp "$root/tmp/frame/frame_00000.ppm" "$work/" 2>/dev/null || true
in_root sh -c 'getent passwd vpe; id -nG vpe; test -d /var/lib/vpe && test -d /etc/vpe && echo folders' \
    >"$work/user.txt" 2>&1 || true
in_root dpkg-query -W -f '${Status} ${Version}\n' vpe-player >"$work/query.txt" 2>&1 || true
in_root sh -c 'dpkg-query -W | wc -l' >"$work/count.txt" 2>&1 || true

check "installed: dpkg-query" grep -q '^install ok installed' "$work/query.txt"
check "vpe-player --check" test "$(cat "$work/check.status")" = 0
check "vpe-player headless frame" test "$(cat "$work/frame.status")" = 0
check "postinst: user vpe" grep -q '^vpe:' "$work/user.txt"
for group in video render gpio input; do
    check "postinst: group $group" grep -qw "$group" "$work/user.txt"
done
check "postinst: /etc/vpe, /var/lib/vpe" grep -qx folders "$work/user.txt"
frame="$work/frame_00000.ppm"
check "frame written" test -s "$frame"
# The frame's mean level (binary PPM, P6 W H 255): a frame of the vase is not black.
frame_stats=$(python3 - "$frame" <<'EOF' 2>/dev/null || echo '{"width": 0, "height": 0, "mean": 0}'
import sys
data = open(sys.argv[1], "rb").read()
fields, pos = [], 0
while len(fields) < 4:
    while data[pos:pos + 1].isspace():
        pos += 1
    end = pos
    while not data[end:end + 1].isspace():
        end += 1
    fields.append(data[pos:end])
    pos = end
pixels = data[pos + 1:]
print('{"width": %d, "height": %d, "mean": %.2f}' % (int(fields[1]), int(fields[2]),
      sum(pixels) / max(len(pixels), 1)))
EOF
)
check "frame not black" python3 -c 'import json,sys; sys.exit(0 if json.loads(sys.argv[1])["mean"] > 1 else 1)' \
    "$frame_stats"

platform=$(grep -o '"platform": "[^"]*"' "$work/frame.txt" | head -n1 | cut -d'"' -f4 || true)
packages=$(tr -dc '0-9' <"$work/count.txt")
seconds=$(python3 -c "import time; print(round(time.time() - $start, 1))")
status=ok
[[ ${#failures[@]} -eq 0 ]] || status=failed
failed_json=$(printf '%s\n' "${failures[@]+"${failures[@]}"}" | python3 -c 'import json,sys; print(json.dumps([l for l in sys.stdin.read().splitlines() if l]))')
python3 - "$name" "$arch" "$depends" "${packages:-0}" "$platform" "$frame_stats" "$seconds" "$status" "$failed_json" \
    "$(head -n1 "$work/check.txt")" <<'EOF'
import json, sys
name, arch, depends, packages, platform, frame, seconds, status, failed, check = sys.argv[1:]
print(json.dumps({"package": name, "arch": arch, "depends": depends,
                  "root_packages": int(packages), "check_first_line": check,
                  "platform": platform, "frame": json.loads(frame), "seconds": float(seconds),
                  "status": status, "failed": json.loads(failed)}))
EOF
[[ $status == ok ]]
