#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The install measurement against real photographs and a noisy camera (docs/install.md,
# "Captures from other tools" and "What a noisy camera costs"):
#   1. procam-calibration's real sample ($VPE_DATA or ../shared/data; skipped when absent):
#        vpe import-graycode   its five poses, OpenCV GrayCodePattern for a 1024x768 projector
#        vpe calibrate --hold-out
#                              the rig, and each pose predicted from the other four's calibration
#        vpe scan              one pose decoded and triangulated (its contact sheet)
#      against the reference the data's README gives (OpenCV 4.6 running the tool's own method);
#   2. the noise sweep on a simulated small room: full well 400 → 20,000 e⁻, raw 10-bit and an
#      ISP's 8-bit gamma 2.2 output (vpe synth-procam --full-well --camera-output; vpe scan
#      --truth), with its plots; and a DLP projector against exposures of 0.3 to 2 frames.
#   scripts/real-procam-report.sh [--out DIR] [--figures DIR]
# --figures (docs/install to refresh the docs) receives the plots and the real pose's sheet.
# The last line of stdout is one JSON object: real_heldout_projector_rms_px,
# real_heldout_per_pose_px, real_stereo_rms_px, real_camera_focal_pct, real_projector_focal_pct,
# real_rotation_deg (vpe's angle between camera and projector; the reference's is 4.11°),
# real_translation_dir_deg (between vpe's T and the reference's), real_import_calibrate_seconds
# (the import, decoding and calibration with the five held-out calibrations),
# noise_sweep (per level: output, full_well, coverage, wrong_code_share, wrong_decode_share (of
# the pixels placed to better than a pixel), wrong_decode_share_with_coarse, coarse_share (placed
# by a Gray bin alone), depth_rms_mm, placed_by), dlp_sweep (per camera exposure in DLP frames:
# coverage, wrong shares, depth_rms_mm, phase_distortion, phase_equalized), seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
out=real-procam-report figures=""
source scripts/lib/report.sh
report_options real-procam-report out figures -- "$@"
[[ -z "$figures" ]] || figures=$(realpath -m "$figures")
start_report
data=${VPE_DATA:-$(realpath -m ../shared/data)}
sample="$data/procam-calibration-sample"
real='{}'

if [[ -d "$sample/capture_0" ]]; then
    step "the real sample: import (vpe import-graycode, 1024x768 projector)"
    start=$(date +%s.%N)
    "$vpe" import-graycode "$sample"/capture_{0..4} --projector 1024x768 --out "$out/real" \
        --json | tail -1 > "$out/import.json"
    step "calibrate, each pose held out (vpe calibrate --hold-out; the board: 10x8 squares, 75 mm)"
    "$vpe" calibrate "$out"/real/capture_{0..4} --board 10x8:75mm --hold-out \
        --out "$out/procam.yml" --json | tail -1 > "$out/calibrate.json"
    decode_seconds=$(awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN { print e - s }')
    step "one pose decoded and triangulated (vpe scan capture_0)"
    "$vpe" scan "$out/real/capture_0" --calibration "$out/procam.yml" --out "$out/real-scan" \
        --min-coverage 0 --json | tail -1 > "$out/real-scan.json"
    # The reference: camera fx 3452.4, projector fx 1942.5, T (90.0, -637.6, -150.4) squares·75.
    real=$(jq -c --argjson seconds "$decode_seconds" '
        def norm(v): (v | map(. * .) | add | sqrt);
        def degrees(x): x * 180 / (1 | atan * 4);
        {real_heldout_projector_rms_px: .heldout_projector_rms_px,
         real_heldout_median_px: .heldout_projector_median_px,
         real_heldout_per_pose_px: [.heldout_per_pose[].rms_px],
         real_stereo_rms_px: .stereo_rms_px,
         real_camera_focal_pct: (100 * (.camera_K[0] / 3452.4 - 1)),
         real_projector_focal_pct: (100 * (.projector_K[0] / 1942.5 - 1)),
         real_rotation_deg: degrees((((.R[0] + .R[4] + .R[8]) - 1) / 2) | if . > 1 then 1 else . end | acos),
         real_translation_dir_deg: degrees(
             ((.T[0] * 90.0 + .T[1] * -637.6 + .T[2] * -150.4)
              / norm(.T) / norm([90.0, -637.6, -150.4])) | acos),
         real_camera_fx: .camera_K[0], real_projector_fx: .projector_K[0],
         real_projector_cx: .projector_K[2], real_projector_cy: .projector_K[5],
         real_import_calibrate_seconds: $seconds}' "$out/calibrate.json")
    echo "$real" | jq . >&2
    if [[ -n "$figures" ]]; then
        mkdir -p "$figures"
        oiiotool "$out/real-scan/contact-sheet.png" --resize 1200x0 -d uint8 \
            -o "$figures/real-pose-decoded.png"
    fi
else
    echo "real-procam-report: $sample not found: the real sample's figures are skipped" >&2
fi

step "the noise sweep (small room: projector 640x360, camera 656x492, phase period 16)"
levels=(400 1000 2000 5000 10000 20000)
sweep="$out/noise-sweep.json"
echo '[]' > "$sweep"
for output in linear10 gamma8; do
    for well in "${levels[@]}"; do
        name="$output-$well"
        "$vpe" synth-procam --out "$out/sweep/$name" --poses 0 --projector-size 640x360 \
            --camera-size 656x492 --phase-period 16 --full-well "$well" \
            --camera-output "$output" >/dev/null 2>&1
        "$vpe" scan "$out/sweep/$name/scan" --calibration "$out/sweep/$name/truth/calibration.yml" \
            --out "$out/sweep/$name/result" --truth "$out/sweep/$name/truth" --min-coverage 0 \
            --json 2>/dev/null | tail -1 > "$out/sweep/$name.json"
        jq -c --arg output "$output" --argjson well "$well" '
            {output: $output, full_well: $well, coverage: .lit_decoded_share,
             wrong_code_share, wrong_decode_share, wrong_decode_share_with_coarse,
             coarse_share, depth_rms_mm, camera_gamma,
             placed_by}' "$out/sweep/$name.json" > "$out/sweep/$name.level.json"
        jq -c '.' "$out/sweep/$name.level.json" >&2
        jq -c --slurpfile level "$out/sweep/$name.level.json" '. + $level' "$sweep" > "$sweep.new"
        mv "$sweep.new" "$sweep"
        rm -rf "$out/sweep/$name"
    done
done
step "a DLP projector against short exposures (vpe synth-procam --dlp-exposure FRAMES)"
dlp="$out/dlp.json"
echo '[]' > "$dlp"
for frames in 0.3 0.5 1.5 2; do
    name="dlp-$frames"
    "$vpe" synth-procam --out "$out/sweep/$name" --poses 0 --projector-size 640x360 \
        --camera-size 656x492 --phase-period 16 --dlp-exposure "$frames" >/dev/null 2>&1
    "$vpe" scan "$out/sweep/$name/scan" --calibration "$out/sweep/$name/truth/calibration.yml" \
        --out "$out/sweep/$name/result" --truth "$out/sweep/$name/truth" --min-coverage 0 \
        --json 2>/dev/null | tail -1 > "$out/sweep/$name.json"
    jq -c --argjson frames "$frames" '
        {exposure_frames: $frames, coverage: .lit_decoded_share, wrong_code_share,
         wrong_decode_share, depth_rms_mm, phase_distortion, phase_equalized}' \
        "$out/sweep/$name.json" > "$out/sweep/$name.level.json"
    jq -c '.' "$out/sweep/$name.level.json" >&2
    jq -c --slurpfile level "$out/sweep/$name.level.json" '. + $level' "$dlp" > "$dlp.new"
    mv "$dlp.new" "$dlp"
    rm -rf "$out/sweep/$name"
done

if [[ -n "$figures" ]]; then
    cmake --build --preset release --target vpe_noise_sweep_plot -j "$(nproc)" >/dev/null
    build/release/tests/benchmarks/vpe_noise_sweep_plot "$sweep" --out "$figures" >&2
fi

jq -c --argjson real "$real" --slurpfile dlp "$dlp" --argjson seconds "$SECONDS" \
    '$real + {noise_sweep: ., dlp_sweep: $dlp[0], seconds: $seconds}' "$sweep"
