#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Measures the light on a simulated gallery whose light is not what vpe used to assume (issue
# 26) and compensates with what was measured: plaster stained ±30 %, a projector whose curves
# are no gamma with crosstalk between its primaries, the room's light at 2 % of the projector's
# white, interreflection, a noisy 10-bit camera. The technician's chain (docs/radiometry.md):
#   vpe synth-procam --scene … --capture N
#                     the scan and the radiometric capture (flat fields), as vpe-player --scan
#                     takes them, twice with fresh noise
#   vpe scan          the surface per projector pixel (the true calibration: the calibration's
#                     own errors are install-report.sh's)
#   vpe radiometry    per projector pixel F and D, the crosstalk, the response, the ambient
#   vpe bake --radiometry, and the same bundle with today's assumed radiometry (albedo 0.85,
#                     gamma 2.2, no ambient)
#   vpe synth-procam --check-light
#                     the camera's view of each bundle's frames on the true installation
#                     against their target, in levels of 255 (4 lights on the visitors' side)
#   scripts/radiometry-report.sh [--out DIR] [--seed N] [--projector-size WxH] [--camera-size WxH]
#                                [--phase-period N]
# The sizes default to vpe synth-procam's (a 1080p projector); the demo passes a smaller room.
# The last line of stdout is one JSON object: rms_levels, baseline_rms_levels, stability_levels,
# clipped_share, seconds (the radiometric capture and fit for the room's projector).
set -euo pipefail
cd "$(dirname "$0")/.."
out=radiometry-report seed=1 projector_size=1920x1080 camera_size=1640x1232 phase_period=32
source scripts/lib/report.sh
report_options radiometry-report out seed projector-size camera-size phase-period -- "$@"
start_report

step "the gallery with its real light (vpe synth-procam --realistic-light, seed $seed)"
room="$out/room"
"$vpe" synth-procam --out "$room" --seed "$seed" --poses 0 --realistic-light \
    --projector-size "$projector_size" --camera-size "$camera_size" --phase-period "$phase_period" \
    --json | tail -1 > "$out/room.json"

step "a texture (vpe synth → fit)"
"$vpe" synth --out "$out/texture/capture" --size 128 --noise camera >&2
"$vpe" fit "$out/texture/capture/train" --out "$out/texture/model.exr" --no-preview >&2

for capture in 1 2; do
    step "capture $capture: scan and flat fields, fresh noise"
    "$vpe" synth-procam --scene "$room/installation.toml" --capture "$capture" \
        --out "$out/capture$capture" --json | tail -1 > "$out/capture$capture.json"
    "$vpe" scan "$out/capture$capture" --calibration "$room/truth/calibration.yml" \
        --out "$out/scan$capture" --json | tail -1 > "$out/scan$capture.json"
    step "capture $capture: vpe radiometry"
    "$vpe" radiometry "$out/capture$capture" --scan "$out/scan$capture" \
        --out "$out/radiometry$capture" --json | tail -1 > "$out/radiometry$capture.json"
    "$vpe" bake --texture "$out/texture/model.exr" --scan "$out/scan$capture" \
        --mesh "$room/object.obj" --radiometry "$out/radiometry$capture" \
        --out "$out/measured$capture.vpeb" --json | tail -1 > "$out/bake$capture.json"
done
step "today's bundle: the assumed radiometry"
"$vpe" bake --texture "$out/texture/model.exr" --scan "$out/scan1" --mesh "$room/object.obj" \
    --out "$out/assumed.vpeb" --json | tail -1 > "$out/bake-assumed.json"

step "what the camera sees of each on the true installation"
"$vpe" synth-procam --scene "$room/installation.toml" --check-light "$out/measured1.vpeb" \
    --baseline "$out/assumed.vpeb" --out "$out/check" --json | tail -1 > "$out/check.json"
step "stability: the second capture's bundle against the first's"
"$vpe" synth-procam --scene "$room/installation.toml" --check-light "$out/measured1.vpeb" \
    --baseline "$out/measured2.vpeb" --out "$out/stability" --json | tail -1 > "$out/stability.json"

capture=$(json .radiometry_capture_seconds "$out/capture1.json")
fit=$(json .seconds "$out/radiometry1.json")
jq -c -n \
    --slurpfile check "$out/check.json" --slurpfile stability "$out/stability.json" \
    --slurpfile measured "$out/radiometry1.json" --slurpfile bake "$out/bake1.json" \
    --argjson capture "$capture" --argjson fit "$fit" \
    '{rms_levels: ($check[0].rms_levels * 1000 | round / 1000),
      baseline_rms_levels: ($check[0].baseline_rms_levels * 1000 | round / 1000),
      stability_levels: ($stability[0].difference_levels * 1000 | round / 1000),
      clipped_share: ($check[0].clipped_share * 10000 | round / 10000),
      seconds: (($capture + $fit) * 100 | round / 100),
      worst_rms_levels: ($check[0].worst_rms_levels * 1000 | round / 1000),
      baseline_worst_rms_levels: ($check[0].baseline_worst_rms_levels * 1000 | round / 1000),
      below_floor_share: ($check[0].below_floor_share * 10000 | round / 10000),
      capture_seconds: ($capture * 100 | round / 100), fit_seconds: ($fit * 100 | round / 100),
      completed_share: ($bake[0].radiometry.completed_pixels / $bake[0].radiometry.covered_pixels
                        * 10000 | round / 10000),
      mixing: $measured[0].mixing, ambient: $measured[0].ambient,
      ambient_sigma: $measured[0].ambient_sigma, camera_black: $measured[0].camera_black,
      projector_black: $measured[0].projector_black}'
