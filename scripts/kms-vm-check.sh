#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# vpe-player's KMS path against a real kernel driver (docs/kms-vm.md): Debian's own kernel in
# qemu-system-x86_64 (TCG, no KVM needed) with a virtio-gpu, a root made by mmdebstrap with
# vpe-player installed from its package (apt-get install ./vpe-player_*.deb), and in the guest:
#   A. the player on /dev/dri/card0 (GBM + EGL through Mesa's kms_swrast/llvmpipe, atomic or
#      legacy modeset, page flips) for a few hundred frames of a moving light (--json and
#      --light-log give frames and the frame interval);
#   B. the packaged systemd unit (Type=notify, WatchdogSec=10) with a still light: every tick is
#      skipped, the watchdog must stay fed for longer than its period; meanwhile the host takes
#      the virtual display with QMP screendump and compares it (PSNR) with the headless frame
#      of the same light rendered in the same root;
#   C. the display going away: QMP device_del of the virtio-gpu while the player flips; the
#      player must end with one clear line, not crash or hang.
# The guest reports on its serial console; the host prints one JSON line and exits non-zero
# when a check failed (2 on bad arguments).
#   scripts/kms-vm-check.sh [WORKDIR [DEB]]
# WORKDIR default /tmp/vpe-kms-vm (replaced); DEB default build/device/vpe-player_*_amd64.deb.
# VPE_KMS_VM_FRAMES: phase A's frames (80: a median and a 99th percentile of the interval). VPE_KMS_VM_REUSE_ROOT=1 keeps WORKDIR's root and
# reference frame from an earlier run (the guest's files are copied in again): for iterating.
# Needs root (mmdebstrap, mkfs.ext4 -d), qemu-system-x86, e2fsprogs, Debian's mirrors. About 6
# minutes here (2 cores shared, TCG).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

fail_usage() { echo "kms-vm-check: $1" >&2; exit 2; }
[[ $# -le 2 ]] || fail_usage "usage: scripts/kms-vm-check.sh [WORKDIR [DEB]]"
work=${1:-/tmp/vpe-kms-vm}
if [[ $# -ge 2 ]]; then
    deb=$2
else
    shopt -s nullglob
    debs=(build/device/vpe-player_*_amd64.deb)
    shopt -u nullglob
    [[ ${#debs[@]} -eq 1 ]] ||
        fail_usage "DEB: expected one build/device/vpe-player_*_amd64.deb (cpack in build/device), found ${#debs[@]}"
    deb=${debs[0]}
fi
[[ -f "$deb" ]] || fail_usage "DEB: $deb: no such file"
deb=$(realpath "$deb")
[[ $(id -u) -eq 0 ]] || fail_usage "must run as root (mmdebstrap, mkfs.ext4 -d)"
for tool in mmdebstrap qemu-system-x86_64 mkfs.ext4 python3; do
    command -v "$tool" >/dev/null || fail_usage "$tool is missing (scripts/install-deps.sh --test)"
done
frames=${VPE_KMS_VM_FRAMES:-80}
[[ "$frames" =~ ^[1-9][0-9]*$ ]] || fail_usage "VPE_KMS_VM_FRAMES: expected a positive integer, got \"$frames\""

start=$(date +%s.%N)
source scripts/lib/debian-root.sh
[[ "$work" == /* ]] || work="$repo/$work"
root="$work/root"
reuse=0
if [[ "${VPE_KMS_VM_REUSE_ROOT:-0}" == 1 && -x "$root/usr/bin/vpe-player" && -s "$work/reference.ppm" ]]; then
    reuse=1
    rm -f "$work/serial.log" "$work/screen.ppm" "$work/root.img"
elif [[ -d "$work" ]]; then
    debian_root_remove "$root"
    rm -rf --one-file-system "$work"
fi
mkdir -p "$work/guest"
qemu_pid=
cleanup() {
    if [[ -n "$qemu_pid" ]]; then
        kill "$qemu_pid" 2>/dev/null || true
    fi
    debian_root_unmount_below "$root"
}
trap cleanup EXIT
log() { echo "kms-vm-check: $*" >&2; }
elapsed() { python3 -c "import time; print(round(time.time() - $start, 1))"; }

# The guest's files: board files (one display mode, 640x360, so llvmpipe under TCG keeps up),
# the check it runs at boot and its unit.
board_common='[display]
backend = "kms"
device = "/dev/dri/card0"
connector = "auto"
mode = "640x360"
modeset = "auto"

[osc]
enabled = false'
printf '[board]\nname = "qemu virtio-gpu, moving light"\n\n%s\n\n[idle]\nenabled = true\nquiet_s = 0\nperiod_s = 8\nhandover_s = 0.5\n' \
    "$board_common" >"$work/guest/kms-moving.toml"
printf '[board]\nname = "qemu virtio-gpu, still light"\n\n%s\n\n[idle]\nenabled = false\n' \
    "$board_common" >"$work/guest/kms-still.toml"
printf '[board]\nname = "headless, still light"\n\n[display]\nbackend = "headless"\n\n[render]\nsize = "projector"\nrate = 60\n\n[osc]\nenabled = false\n\n[idle]\nenabled = false\n' \
    >"$work/guest/headless-still.toml"
cat >"$work/guest/vpe-kms-guest" <<'EOF'
#!/bin/sh
# The guest's side of scripts/kms-vm-check.sh: every line for the host starts with VPE-.
exec >/dev/ttyS0 2>&1
bundle=/usr/share/vpe/examples/vase-640x360.vpeb
say() { echo "VPE-$*"; }
say "GUEST-START uptime $(cut -d' ' -f1 /proc/uptime)"
i=0
while [ ! -e /dev/dri/card0 ] && [ $i -lt 60 ]; do sleep 1; i=$((i + 1)); done
say "DRI $(ls /dev/dri | tr '\n' ' ')$(dmesg | grep -o '\[drm\] Initialized [a-z_]* [0-9.]*' | head -n1)"
for c in /sys/class/drm/card0-*; do say "CONNECTOR $(basename "$c") $(cat "$c/status") $(head -n1 "$c/modes")"; done

# A: a moving light on the KMS display.
vpe-player --board /etc/vpe/kms-moving.toml --bundle $bundle --frames @FRAMES@ --json \
    --light-log /run/light.jsonl >/run/a.out 2>&1
say "A-STATUS $?"
sed 's/^/VPE-A /' /run/a.out
sed 's/^/VPE-LIGHT /' /run/light.jsonl

# B: the packaged unit with a still light: skipped ticks, the watchdog fed.
cp /etc/vpe/kms-still.toml /etc/vpe/board.toml
cp $bundle /var/lib/vpe/scene.vpeb
systemctl start vpe-player.service
say "B-START $?"
say "SCREENDUMP-READY"
sleep 15  # one and a half watchdog periods
say "B-STATE $(systemctl show -p ActiveState -p SubState -p NRestarts -p Result -p WatchdogUSec vpe-player.service | tr '\n' ' ')"
systemctl stop vpe-player.service
journalctl -b -u vpe-player.service -o cat --no-pager | sed 's/^/VPE-B-LOG /'

# C: the display goes away under the packaged unit while it flips. The host first asks qemu to
# unplug the virtio-gpu (QMP device_del); qemu refuses for this device, so the guest removes
# the PCI function itself (sysfs remove: the driver's unbind and drm_dev_unplug, the kernel's
# path of a GPU that is gone), then reports what the unit and the player did.
cp /etc/vpe/kms-moving.toml /etc/vpe/board.toml
sleep 1  # B's last lines in an earlier second than C's first
since=$(date '+%Y-%m-%d %H:%M:%S')
systemctl start vpe-player.service
sleep 8
say "UNPLUG-READY"
sleep 5
dev=$(basename "$(readlink -f /sys/class/drm/card0/device)")
say "C-REMOVE $dev $(date +%s.%N)"
echo 1 >"/sys/bus/pci/devices/$dev/remove"
sleep 20  # a hung player is killed by the watchdog within 10 s
say "C-STATE $(systemctl show -p ActiveState -p SubState -p NRestarts -p Result -p ExecMainStatus -p ExecMainCode vpe-player.service | tr '\n' ' ')"
systemctl stop vpe-player.service
journalctl -u vpe-player.service --since "$since" -o short-monotonic --no-pager | sed 's/^/VPE-C-LOG /'
say "C-DRI $(ls /dev/dri 2>/dev/null | tr '\n' ' ')"
dmesg | grep -iE 'virtio_gpu|drm' | tail -n 4 | sed 's/^/VPE-C-DMESG /'
say "GUEST-DONE uptime $(cut -d' ' -f1 /proc/uptime)"
systemctl poweroff
EOF
sed -i "s/@FRAMES@/$frames/" "$work/guest/vpe-kms-guest"
cat >"$work/guest/vpe-kms-guest.service" <<'EOF'
[Unit]
Description=scripts/kms-vm-check.sh: the guest's side
After=multi-user.target

[Service]
Type=oneshot
TimeoutStartSec=infinity
ExecStart=/usr/local/sbin/vpe-kms-guest

[Install]
WantedBy=multi-user.target
EOF

# The root: Debian 12 with its kernel and systemd, vpe-player from its package; the reference
# frame rendered headless in the same root (same binary, same Mesa) before the image is made.
# The root starts as a copy of a base root with the kernel, systemd and the packages the
# package's Depends names, made by mmdebstrap from Debian once per state of the archive
# (root_cache_device_base in scripts/lib/root-cache.sh; scripts/device-roots.sh makes it ahead);
# the package itself is installed with apt every run.
source scripts/lib/root-cache.sh
debian_root_sources "$work" || exit 2
name=$(basename "$deb")
cp "$deb" "$work/"
if [[ $reuse -eq 0 ]]; then
    log "root ($(elapsed) s)"
    if ! root_cache_kms_vm_base "$root" "$work/$name" 2>"$work/mmdebstrap.log"; then
        tail -n 20 "$work/mmdebstrap.log" >&2
        log "the base root could not be made (see $work/mmdebstrap.log)"
        exit 1
    fi
    log "base root ready ($(elapsed) s)"
    cp "$work/$name" "$root/tmp/"
    if ! root_cache_chroot "$root" sh -c "cd /tmp && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ./$name" \
        >"$work/install.log" 2>&1; then
        tail -n 20 "$work/install.log" >&2
        log "apt-get install ./$name failed (see $work/install.log)"
        exit 1
    fi
    rm -f "$root/tmp/$name"
    mkdir -p "$root/etc/vpe"
    cp "$work/guest/headless-still.toml" "$root/etc/vpe/"
    if ! root_cache_chroot "$root" vpe-player --board /etc/vpe/headless-still.toml \
        --bundle /usr/share/vpe/examples/vase-640x360.vpeb --frames 1 --out /var/tmp/reference \
        >"$work/reference.txt" 2>&1; then
        tail -n 5 "$work/reference.txt" >&2
        log "the headless reference frame failed (see $work/reference.txt)"
        exit 1
    fi
    cp "$root/var/tmp/reference/frame_00000.ppm" "$work/reference.ppm"
fi
# The guest's files, its unit enabled; no getty on the serial console: agetty's vhangup() would
# cut off the check's own writes to /dev/ttyS0.
mkdir -p "$root/etc/vpe" "$root/usr/local/sbin" "$root/etc/systemd/system/multi-user.target.wants"
cp "$work"/guest/*.toml "$root/etc/vpe/"
install -m 0755 "$work/guest/vpe-kms-guest" "$root/usr/local/sbin/"
cp "$work/guest/vpe-kms-guest.service" "$root/etc/systemd/system/"
ln -sf /etc/systemd/system/vpe-kms-guest.service \
    "$root/etc/systemd/system/multi-user.target.wants/vpe-kms-guest.service"
ln -sf /dev/null "$root/etc/systemd/system/serial-getty@ttyS0.service"
echo vpe-kms-vm >"$root/etc/hostname"
kernel=$(ls "$root"/boot/vmlinuz-* | tail -n1)
initrd=$(ls "$root"/boot/initrd.img-* | tail -n1)
cp "$kernel" "$work/vmlinuz"
cp "$initrd" "$work/initrd.img"
size_mb=$(($(du -sm "$root" | cut -f1) + 400))
mkfs.ext4 -q -F -L vperoot -d "$root" "$work/root.img" "${size_mb}M"
log "image ${size_mb} MB, kernel $(basename "$kernel") ($(elapsed) s)"

# The VM: i440fx (ACPI PCI hotplug, for C), TCG, the virtio-gpu's preferred mode 640x360,
# serial console to a file, QMP on a socket. -no-reboot: the guest's poweroff ends qemu.
serial="$work/serial.log"
: >"$serial"
qemu-system-x86_64 -machine pc,accel=tcg -m 2048 -smp 2 -display none -vga none \
    -device virtio-gpu-pci,id=gpu,xres=640,yres=360 \
    -drive file="$work/root.img",format=raw,if=virtio \
    -kernel "$work/vmlinuz" -initrd "$work/initrd.img" \
    -append "root=/dev/vda rw console=ttyS0 quiet loglevel=3 systemd.show_status=false" \
    -serial file:"$serial" -qmp unix:"$work/qmp.sock",server=on,wait=off \
    -monitor none -no-reboot >"$work/qemu.log" 2>&1 &
qemu_pid=$!
qmp() {  # qmp JSON-COMMAND: prints the reply (the line with "return" or "error")
    python3 - "$work/qmp.sock" "$1" <<'EOF'
import json, socket, sys
s = socket.socket(socket.AF_UNIX)
s.settimeout(60)
s.connect(sys.argv[1])
f = s.makefile("rw")
f.readline()
for command in ({"execute": "qmp_capabilities"}, json.loads(sys.argv[2])):
    f.write(json.dumps(command) + "\n")
    f.flush()
    while True:
        reply = json.loads(f.readline())
        if "return" in reply or "error" in reply:
            break
print(json.dumps(reply))
EOF
}
wait_for() {  # wait_for MARKER SECONDS
    local deadline=$(($(date +%s) + $2))
    while ! grep -q "^$1" "$serial"; do
        if ! kill -0 "$qemu_pid" 2>/dev/null || [[ $(date +%s) -ge $deadline ]]; then
            return 1
        fi
        sleep 1
    done
}
screendump=none
unplug=none
if wait_for VPE-SCREENDUMP-READY 420; then
    log "screendump ($(elapsed) s)"
    screendump=$(qmp "{\"execute\": \"screendump\", \"arguments\": {\"filename\": \"$work/screen.ppm\"}}")
fi
if wait_for VPE-UNPLUG-READY 120; then
    log "device_del gpu ($(elapsed) s)"
    unplug=$(qmp '{"execute": "device_del", "arguments": {"id": "gpu"}}')
fi
deadline=$(($(date +%s) + 150))
while kill -0 "$qemu_pid" 2>/dev/null && [[ $(date +%s) -lt $deadline ]]; do sleep 1; done
if kill -0 "$qemu_pid" 2>/dev/null; then
    log "the guest did not power off; stopping qemu"
    kill "$qemu_pid"
fi
wait "$qemu_pid" 2>/dev/null || true
qemu_pid=
log "guest done ($(elapsed) s)"

# The figures, from the guest's lines and the two images.
python3 - "$serial" "$work/reference.ppm" "$work/screen.ppm" "$screendump" "$unplug" "$(elapsed)" \
    "$frames" <<'EOF'
import json, math, re, sys
serial, reference, screen, screendump, unplug, seconds, wanted = sys.argv[1:]
lines = open(serial, errors="replace").read().splitlines()
def tagged(tag):
    prefix = "VPE-" + tag + " "
    return [l[len(prefix):] for l in lines if l.startswith(prefix)]
def first(tag, default=""):
    found = tagged(tag)
    return found[0] if found else default
failures = []
result = {}

# A: the player's own report and light log.
report = next((json.loads(l) for l in tagged("A") if l.startswith("{")), None)
if report is None:
    failures.append("A: no --json report")
    report = {}
result["platform"] = report.get("platform", "")
result["modeset"] = ("atomic" if "(atomic modesetting)" in result["platform"] else
                     "legacy" if "(legacy modesetting)" in result["platform"] else "unknown")
result["frames"] = report.get("frames", 0)
result["skipped_a"] = report.get("skipped", 0)
result["errors_a"] = report.get("errors", 0)
# Frame 0 is the synchronous modeset; every later frame is started by the page flip of the one
# before (firmware/README.md, "Pacing").
result["flips"] = max(result["frames"] - 1, 0)
drawn = [json.loads(l)["t_us"] for l in tagged("LIGHT") if '"drawn": true' in l]
intervals = sorted((b - a) / 1000.0 for a, b in zip(drawn, drawn[1:]))
def rank(q):
    return round(intervals[min(len(intervals), max(1, math.ceil(q * len(intervals)))) - 1], 2) if intervals else 0
result["interval_ms"] = {"p50": rank(0.5), "p99": rank(0.99), "count": len(intervals)}
result["frame_ms"] = report.get("frame_ms", {})
if first("A-STATUS") != "0":
    failures.append("A: exit status " + first("A-STATUS", "?"))
if result["frames"] < int(wanted) * 0.9:
    failures.append("A: %d frames of %s" % (result["frames"], wanted))
if result["modeset"] == "unknown":
    failures.append("A: no KMS platform")
# Paced by the flips: a frame starts when the previous one's flip is done, so the interval is
# the frame's own time plus the wait for the next vblank — at most one refresh period more.
refresh = re.search(r"@(\d+) \(", result["platform"])
period_ms = 1000.0 / int(refresh.group(1)) if refresh else 16.7
result["refresh_hz"] = int(refresh.group(1)) if refresh else None
frame_p50 = result["frame_ms"].get("p50", 0)
if intervals and not frame_p50 - 1 <= rank(0.5) <= frame_p50 + period_ms + 2:
    failures.append("A: median frame interval %.1f ms for frames of %.1f ms at %.0f Hz"
                    % (rank(0.5), frame_p50, 1000 / period_ms))

# B: the unit's state after 15 s of skipped ticks.
state = dict(kv.split("=", 1) for kv in first("B-STATE").split() if "=" in kv)
result["watchdog"] = {"state": state.get("ActiveState", ""), "restarts": state.get("NRestarts", ""),
                      "watchdog_usec": state.get("WatchdogUSec", "")}
if state.get("ActiveState") != "active" or state.get("NRestarts") != "0":
    failures.append("B: unit %s, restarts %s" % (state.get("ActiveState"), state.get("NRestarts")))

# The screendump against the headless frame of the same light.
def ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    return int(fields[1]), int(fields[2]), data[pos + 1:]
try:
    w1, h1, a = ppm(reference)
    w2, h2, b = ppm(screen)
    if (w1, h1) != (w2, h2):
        raise ValueError("sizes %dx%d and %dx%d" % (w1, h1, w2, h2))
    mse = sum((x - y) ** 2 for x, y in zip(a, b)) / len(a)
    result["psnr_db"] = round(10 * math.log10(255 ** 2 / mse), 2) if mse > 0 else "inf"
    result["screen"] = "%dx%d" % (w2, h2)
    if mse > 0 and result["psnr_db"] < 40:
        failures.append("B: screendump PSNR %.1f dB" % result["psnr_db"])
except (OSError, ValueError, IndexError) as error:
    result["psnr_db"] = None
    failures.append("B: screendump: %s (%s)" % (error, screendump))

# C: the display gone under the unit.
c_log = tagged("C-LOG")
c_state = dict(kv.split("=", 1) for kv in first("C-STATE").split() if "=" in kv)
player_lines = [l for l in c_log if re.search(r"vpe-player\[\d+\]: vpe-player: ", l)]
# Clean: the player says what happened in one line and exits, and the unit's restarts say the
# display is missing (until it comes back). Not clean: the player stops drawing and pinging and
# the watchdog has to kill it (hung), or it dies of a signal of its own (crashed).
watchdog_killed = any("Watchdog timeout" in l for l in c_log)
crashed = not watchdog_killed and any(re.search(r"dumped core|status=(6|11)/", l) for l in c_log)
first_line = next((re.sub(r"^\[[ 0-9.]*\] \S+ ", "", l) for l in player_lines), "")
result["connector_loss"] = {
    "qmp_device_del": (json.loads(unplug).get("error", {}).get("desc", "ok")
                       if unplug.startswith("{") else unplug),
    "method": "guest sysfs PCI remove of " + first("C-REMOVE", "?").split(" ")[0],
    "unit": c_state, "first_player_line": first_line, "hung_until_watchdog": watchdog_killed,
    "crashed": crashed,
    "player_lines": [re.sub(r"^\[[ 0-9.]*\] \S+ ", "", l) for l in player_lines[-4:]],
    "dri_after": first("C-DRI"), "dmesg": tagged("C-DMESG")[-2:]}
if crashed:
    failures.append("C: the player crashed when the display went away")
elif watchdog_killed:
    failures.append("C: the player stopped when the display went away and the watchdog killed it")
elif not player_lines:
    failures.append("C: the player said nothing when the display went away")
if not tagged("GUEST-DONE"):
    failures.append("guest: did not finish")
result["guest_uptime_s"] = first("GUEST-DONE").replace("uptime ", "")
result["seconds"] = float(seconds)
result["status"] = "ok" if not failures else "failed"
result["failed"] = failures
print(json.dumps(result))
sys.exit(0 if not failures else 1)
EOF
