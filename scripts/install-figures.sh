#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates the pictures and tables of docs/install.md on the simulated gallery:
#   - the calibration's corners, a good scan's contact sheet and the visitor check, from an
#     install report (scripts/install-report.sh; --from DIR reuses one);
#   - where to put the camera: coverage and depth error of a scan with the camera 10, 21 and
#     33 cm from the projector;
#   - what a bad scan looks like: a camera that saturates (exposure too long) and a bright room.
# Pictures go to the --out folder; the table and the bad scans' figures to stdout.
#   scripts/install-figures.sh [--from REPORT_DIR] [--out docs/install]
set -euo pipefail
cd "$(dirname "$0")/.."
from="" out=docs/install
source scripts/lib/report.sh
report_options install-figures from out -- "$@"
[[ -z "$from" ]] || from=$(realpath -m "$from")
start_report --keep-out
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [[ -z "$from" ]]; then
    from="$work/report"
    scripts/install-report.sh --out "$from" | tail -1 > "$work/report.json"
fi

# picture IN OUT WIDTH: a copy at most WIDTH pixels wide, 8-bit PNG.
picture() {
    oiiotool "$1" --resize "$3x0" -d uint8 -o "$2"
}
picture "$from/procam-poses.png" "$out/calibration-poses.png" 1200
picture "$from/scan-true/contact-sheet.png" "$out/scan-good.png" 1200
picture "$from/check/visitor-check.png" "$out/visitor-check.png" 960

# scan_variant NAME ARGS...: a gallery without calibration poses, scanned with its true
# calibration; prints "coverage depth_rms_mm undecoded-share".
scan_variant() {
    local name=$1
    shift
    "$vpe" synth-procam --out "$work/$name" --poses 0 "$@" >&2
    "$vpe" scan "$work/$name/scan" --calibration "$work/$name/truth/calibration.yml" \
        --out "$work/$name/result" --truth "$work/$name/truth" --min-coverage 0 --json \
        | tail -1 > "$work/$name.json"
    jq -r '"\(.scan_coverage) \(.depth_rms_mm) \(1 - .decoded_share)"' "$work/$name.json"
}

# The tables and figures for docs/install.md go to stdout.
table="$work/camera-offset.txt"
printf '| camera to the projector | coverage of what the camera sees | depth RMS |\n' > "$table"
printf '|---|---|---|\n' >> "$table"
for offset in 0.10 0.21 0.33; do
    read -r coverage depth _ < <(scan_variant "offset-$offset" --camera-offset "$offset")
    printf '| %.0f cm | %.2f %% | %.3f mm |\n' "$(awk -v o="$offset" 'BEGIN { print o * 100 }')" \
        "$(awk -v c="$coverage" 'BEGIN { print 100 * c }')" "$depth" >> "$table"
done
cat "$table"

read -r coverage depth undecoded < <(scan_variant saturated --exposure 1.3)
picture "$work/saturated/result/contact-sheet.png" "$out/scan-saturated.png" 1200
printf 'saturated (exposure 1.3): coverage %.2f %%, undecoded %.1f %%\n' \
    "$(awk -v c="$coverage" 'BEGIN { print 100 * c }')" \
    "$(awk -v u="$undecoded" 'BEGIN { print 100 * u }')"
read -r coverage depth undecoded < <(scan_variant bright-room --room-light 1.2)
picture "$work/bright-room/result/contact-sheet.png" "$out/scan-bright-room.png" 1200
printf 'bright room (room light 1.2): coverage %.2f %%, depth RMS %.3f mm, undecoded %.1f %%\n' \
    "$(awk -v c="$coverage" 'BEGIN { print 100 * c }')" "$depth" \
    "$(awk -v u="$undecoded" 'BEGIN { print 100 * u }')"
echo "wrote $out" >&2
