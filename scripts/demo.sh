#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The demo: the whole pipeline built so far, end to end, writing pictures to demo-output/
# (or $1). It renders the built-in synthetic Bizen capture, fits the paper's Fourier BRDF
# and vpe's extended model, scores them on held-out lights, reproduces the paper's Fig. 6,
# splits the texture into regions, quilts each to a new texture sized for the vase (the
# capture's texel as long on it, tiling around it) and blends them with
# weight maps, bakes a device bundle for a vase and a projector, renders frames for a moving
# light with the CPU reference (projector, visitor and material views), plays the bundle on
# the device program (vpe-player: OpenGL ES, headless) along its idle path, and lays the
# results out as contact sheets; installs vpe on a simulated gallery (calibrate, scan,
# register, bake, check: scripts/install-report.sh); then does the same fits on real captures
# when ../shared/data (or $VPE_DATA) has them. Installs missing Debian packages itself (the
# test ones too: the release build it shares with scripts/test.sh configures the tests and
# benchmarks, and the demo runs two of the benchmarks on its bundle), and ffmpeg for its
# animation.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test --demo
source scripts/lib/pictures.sh
source scripts/lib/report.sh  # build_vpe, step

started=$(date +%s)
out=$(realpath -m "${1:-demo-output}")
data=${VPE_DATA:-$(realpath -m ../shared/data)}
build_vpe
rm -rf "$out"
mkdir -p "$out"
summary="$out/summary.txt"
: > "$summary"

# run_report NAME [OPTION...]: scripts/NAME-report.sh into $out/NAME (which the report empties
# first), its JSON line (the last of its stdout) kept there as NAME.json; $report names that file.
run_report() {
    local name=$1
    shift
    scripts/"$name"-report.sh --out "$out/$name" "$@" | tail -1 > "$out/$name.json"
    mv "$out/$name.json" "$out/$name/$name.json"
    report="$out/$name/$name.json"
}
# The simulated galleries of the install and radiometry steps: the tests' small room (a 640 × 360
# projector, a 656 × 492 camera, 6 board poses), which shows every step of the chain and its
# figures in a sixth of the 1080p room's time; the reports' defaults make the docs' figures at
# full size (docs/install.md, docs/radiometry.md).
small_room=(--projector-size 640x360 --camera-size 656x492 --phase-period 16)

# Fits the paper's model and the extended one to TRAIN, predicts TEST, records the PSNRs.
fit_and_score() {  # name train test
    local name=$1 train=$2 test=$3 dir="$out/$1"
    mkdir -p "$dir"
    "$vpe" fit "$train" --out "$dir/paper.exr" --json > "$dir/paper-fit.json"
    "$vpe" eval "$dir/paper.exr" "$test" --predictions "$dir/paper-test" --json > "$dir/paper-eval.json"
    "$vpe" fit "$train" --out "$dir/extended.exr" --model extended --json > "$dir/extended-fit.json"
    "$vpe" eval "$dir/extended.exr" "$test" --predictions "$dir/extended-test" --json \
        > "$dir/extended-eval.json"
    printf '%-28s held-out PSNR: paper %6.2f dB, extended %6.2f dB\n' "$name" \
        "$(json_field psnr < "$dir/paper-eval.json")" "$(json_field psnr < "$dir/extended-eval.json")" \
        | tee -a "$summary"
}

# Rows of held-out lights (truth | paper | extended); tiles go to DIR/tiles.
prediction_rows() {  # dir test-folder truth-encoding extension light...
    local dir=$1 test=$2 encoding=$3 extension=$4
    shift 4
    mkdir -p "$dir/tiles"
    for light in "$@"; do
        tile "$test/$light$extension" "$dir/tiles/$light-truth.png" "truth, $light" "$encoding"
        tile "$dir/paper-test/$light.png" "$dir/tiles/$light-paper.png" "paper M=10"
        tile "$dir/extended-test/$light.png" "$dir/tiles/$light-extended.png" "extended"
        rows+=("$dir/tiles/$light-truth.png" "$dir/tiles/$light-paper.png" "$dir/tiles/$light-extended.png")
    done
}

step "the built-in synthetic Bizen capture (vpe synth: paper rig, camera noise)"
synthetic="$out/synthetic-bizen"
"$vpe" synth --out "$synthetic/capture" --size 160 --noise camera
fit_and_score synthetic-bizen "$synthetic/capture/train" "$synthetic/capture/test"
rows=()
prediction_rows "$synthetic" "$synthetic/capture/test" linear .png light002 light004 light011 light017
channels_picture "$synthetic/paper.exr" rms.R,rms.G,rms.B "$synthetic/tiles/rms-map.png" 20 0
tile "$synthetic/tiles/rms-map.png" "$synthetic/tiles/rms.png" "fit RMS x20 (paper)"
channels_picture "$synthetic/paper.exr" normal.X,normal.Y,normal.Z "$synthetic/tiles/normal-map.png" 0.5 0.5
tile "$synthetic/tiles/normal-map.png" "$synthetic/tiles/normals.png" "normal map"
tile "$synthetic/capture/truth/labels-preview.png" "$synthetic/tiles/labels.png" "materials (truth)"
sheet 3 "$synthetic/contact-sheet.png" "${rows[@]}" \
    "$synthetic/tiles/rms.png" "$synthetic/tiles/normals.png" "$synthetic/tiles/labels.png"
step "the paper's Fig. 6 on it (vpe sweep)"
mkdir -p "$synthetic/sweep"
"$vpe" sweep "$synthetic/capture/train" "$synthetic/capture/test" --out "$synthetic/sweep" \
    | tee "$synthetic/sweep/table.txt"

step "texture: regions (vpe segment) → region quilting (vpe quilt) → weight maps (vpe compose)"
texture="$synthetic/texture"
mkdir -p "$texture/tiles"
"$vpe" segment "$synthetic/paper.exr" --out "$texture/labels.png" --auto auto \
    --truth "$synthetic/capture/truth/labels.png" --average "$texture/average.png" --json \
    > "$texture/segment.json"
"$vpe" quilt "$synthetic/paper.exr" --labels "$texture/labels.png" --size auto \
    --out "$texture/quilt" --json > "$texture/quilt.json"
"$vpe" quilt-quality "$synthetic/paper.exr" --labels "$texture/labels.png" --quilt "$texture/quilt" \
    --json > "$texture/quilt-quality.json"
# Hidasuki strokes with the source's own streak coverage and widths: label 0 is the streaks
# (labels are ordered by luminance; the red-brown streaks are darker than the ground).
strokes="strokes:from=$texture/labels.png:region=0"
"$vpe" compose "$texture/quilt" --out "$texture/composed.exr" \
    --weights "$strokes,$strokes:invert" \
    --weights-out "$texture/weights.png" --json > "$texture/compose.json"
light=0.45,0.35,1
"$vpe" relight "$synthetic/paper.exr" --light "$light" --out "$texture/source-relit.png"
for region in 0 1; do
    "$vpe" relight "$texture/quilt/region$region.exr" --light "$light" --out "$texture/region$region-relit.png"
done
"$vpe" relight "$texture/composed.exr" --light "$light" --out "$texture/composed-relit.png"
printf '%-28s regions: mean IoU %.3f vs the true materials (K = %s chosen by silhouette)\n' \
    "synthetic-bizen" "$(json_field mean_iou < "$texture/segment.json")" \
    "$(json_field clusters < "$texture/segment.json")" | tee -a "$summary"
printf '%-28s quilted 2 regions to %sx%s (texels %.2f mm, stretch on the vase: median %.2f, p95 %.2f; u seam %.2fx the interior step) in %.2f s\n' "" \
    "$(jq .width "$texture/quilt.json")" "$(jq .height "$texture/quilt.json")" \
    "$(jq .texel_mm "$texture/quilt.json")" "$(jq .stretch.median "$texture/quilt.json")" \
    "$(jq .stretch.p95 "$texture/quilt.json")" "$(jq '[.seams[].ratio] | max' "$texture/quilt.json")" \
    "$(jq .seconds "$texture/quilt.json")" | tee -a "$summary"
tile "$texture/average.png" "$texture/tiles/1.png" "average (dome)"
tile "$texture/labels-overlay.png" "$texture/tiles/2.png" "vpe segment --auto auto"
tile "$texture/source-relit.png" "$texture/tiles/3.png" "source, one light"
tile "$texture/region0-relit.png" "$texture/tiles/4.png" "quilted region 0"
tile "$texture/region1-relit.png" "$texture/tiles/5.png" "quilted region 1"
tile "$texture/composed-relit.png" "$texture/tiles/7.png" "composed, same light"
sheet 3 "$texture/contact-sheet.png" "$texture"/tiles/{1,2,3,4,5,7}.png
rm -rf "$texture/tiles"

step "bake (vpe bake) and render (vpe render): the screen vase, a projector, a light moving around"
stage="$synthetic/projection"
mkdir -p "$stage/frames" "$stage/tiles"
"$vpe" bake --quilt "$texture/quilt" \
    --preset "strokes=$strokes,$strokes:invert" \
    --preset "stripes=stripes:angle=60:period=48:sharpness=4,stripes:angle=60:period=48:sharpness=4:invert" \
    --out "$stage/scene.vpeb" --json > "$stage/bake.json"
"$vpe" info "$stage/scene.vpeb" > "$stage/info.txt"
frame=0
for angle in 0 45 90 135 180 225 270 315; do
    light=$(awk -v a="$angle" 'BEGIN { r = 0.5; t = a * 3.14159265 / 180;
                                      printf "%.4f,%.4f,%.4f", r * sin(t), 0.3, 0.2 + r * cos(t) }')
    name=$(printf 'frame%02d' "$frame")
    "$vpe" render "$stage/scene.vpeb" --light "$light" --gain 0.5 --exposure 6 --view-fov 12 \
        --out "$stage/frames/$name-projector.png" --simulate "$stage/frames/$name-visitor.png" \
        --direct "$stage/frames/$name-material.png" --json > "$stage/frames/$name.json"
    tile "$stage/frames/$name-projector.png" "$stage/tiles/$name-1.png" "projector, light at $angle deg"
    tile "$stage/frames/$name-visitor.png" "$stage/tiles/$name-2.png" "visitor sees (simulated)"
    tile "$stage/frames/$name-material.png" "$stage/tiles/$name-3.png" "the material itself"
    frame=$((frame + 1))
done
sheet 6 "$stage/contact-sheet.png" "$stage"/tiles/*.png
rm -rf "$stage/tiles"
printf '%-28s baked %s bytes (%s bytes/texel per region); 8 frames rendered, loop closed to %.1f dB (frame 0)\n' "" \
    "$(json_field bytes < "$stage/bake.json")" "$(json_field bytes_per_texel < "$stage/bake.json")" \
    "$(json_field psnr < "$stage/frames/frame00.json")" | tee -a "$summary"

step "animation: what a visitor sees while the light circles the vase (vpe render, ffmpeg)"
movie="$stage/animation"
mkdir -p "$movie"
# 96 lights, one turn at the contact sheet's radius and height: 4 s at 24 frames a second. A
# frame renders in about a second and gains little from a second thread, so the frames render
# one per core, side by side.
render_turn_frame() {  # index
    local light name
    light=$(awk -v i="$1" 'BEGIN { r = 0.5; t = 2 * 3.14159265 * i / 96;
                                  printf "%.4f,%.4f,%.4f", r * sin(t), 0.3, 0.2 + r * cos(t) }')
    name=$(printf '%03d' "$1")
    "$vpe" render "$stage/scene.vpeb" --light "$light" --gain 0.5 --exposure 6 --view-fov 12 \
        --threads 1 --out "$movie/projector$name.png" --simulate "$movie/visitor$name.png" \
        --direct "$movie/material$name.png" 2>/dev/null
}
export -f render_turn_frame
export vpe stage movie
seq 0 95 | xargs -P "$(nproc)" -I{} bash -c 'render_turn_frame {}'
# Left the white vase lit by the projector (simulated), right the material itself.
ffmpeg -loglevel error -y -framerate 24 -i "$movie/visitor%03d.png" -framerate 24 \
    -i "$movie/material%03d.png" -filter_complex hstack -c:v libx264 -pix_fmt yuv420p -crf 18 \
    -movflags +faststart "$movie/partial.mp4"
mv "$movie/partial.mp4" "$stage/visitor.mp4"
rm -rf "$movie"
printf '%-28s animation: projection/visitor.mp4, 96 frames (visitor sees | the material)\n' "" \
    | tee -a "$summary"

step "play (vpe-player, OpenGL ES headless): the light drifting along the idle path"
play="$synthetic/player"
mkdir -p "$play/frames" "$play/tiles"
# The headless board at 4 frames a second (llvmpipe renders a 1080p frame in about 0.13 s), its
# drift set to one loop in 8 s: the 32 frames are one loop of the figure of eight.
sed -e 's/^rate = .*/rate = 4/' -e 's/^period_s = .*/period_s = 8/' -e 's/^handover_s = .*/handover_s = 0/' \
    -e '/^\[osc\]/,/^port/ s/^enabled = true/enabled = false/' \
    boards/headless.toml > "$play/board.toml"
"$player" --board "$play/board.toml" --bundle "$stage/scene.vpeb" --frames 32 --every 2 \
    --out "$play/frames" --json > "$play/player.txt"
tail -1 "$play/player.txt" > "$play/player.json"
for ppm in "$play"/frames/frame_*.ppm; do
    name=$(basename "$ppm" .ppm)
    oiiotool "$ppm" -d uint8 -o "$play/frames/$name.png" && rm "$ppm"
    # The tiles show the vase: the middle of the projector's frame.
    oiiotool "$play/frames/$name.png" --cut 640x600+640+230 -o "$play/tiles/$name-vase.png"
    index=$((10#${name#frame_}))
    tile "$play/tiles/$name-vase.png" "$play/tiles/$name.png" \
        "frame $index, t = $(awk -v i="$index" 'BEGIN { printf "%.2f", i / 4 }') s"
    rm "$play/tiles/$name-vase.png"
done
sheet 4 "$play/contact-sheet.png" "$play"/tiles/*.png
rm -rf "$play/tiles"
printf '%-28s vpe-player (GLES, %s): 32 frames 1920x1080, frame p50 %.0f ms; first frame %.0f ms after start\n' "" \
    "$(sed -n 's/.*"platform": "\([^:(]*\).*/\1/p' "$play/player.json" | sed 's/ *$//')" \
    "$(sed -n 's/.*"frame_ms": {"p50": \([0-9.]*\).*/\1/p' "$play/player.json")" \
    "$(json_field first_frame_ms < "$play/player.json")" | tee -a "$summary"

step "the device's speed and fidelity on this bundle (unpaced vpe-player; GPU against the exact CPU frame)"
cmake --build --preset release --target vpe_gles_fidelity -j "$(nproc)" >/dev/null
"$player" --board boards/headless.toml --rate 0 --bundle "$stage/scene.vpeb" --frames 240 \
    --size 1920x1080 --json > "$play/unpaced.txt"
tail -1 "$play/unpaced.txt" > "$play/unpaced.json"
build/release/tests/benchmarks/vpe_gles_fidelity "$stage/scene.vpeb" --json > "$play/fidelity.txt"
tail -1 "$play/fidelity.txt" > "$play/fidelity.json"
head -n -1 "$play/fidelity.txt" >&2
printf '%-28s vpe-player unpaced, 240 frames 1920x1080: %.0f fps (frame p50 %.1f ms)\n' "" \
    "$(jq .fps "$play/unpaced.json")" "$(jq .frame_ms.p50 "$play/unpaced.json")" | tee -a "$summary"
printf '%-28s GPU frames vs the exact CPU reference, 8 lights: worst %.1f dB on the vase, %.1f dB over the frame\n' "" \
    "$(jq .psnr_object_worst "$play/fidelity.json")" "$(jq .psnr_frame_worst "$play/fidelity.json")" \
    | tee -a "$summary"

step "transfer fidelity (scripts/transfer-report.sh): the true material vs the pipeline on the vase"
mkdir -p "$synthetic/transfer"
scripts/transfer-report.sh --capture "$synthetic/capture" --out "$synthetic/transfer" \
    | tail -1 > "$synthetic/transfer/transfer.json"
printf '%-28s transfer fidelity, 8 new lights and views: %.2f dB, SSIM %.4f (extended, relief carried)\n' "" \
    "$(jq .psnr "$synthetic/transfer/transfer.json")" "$(jq .ssim "$synthetic/transfer/transfer.json")" \
    | tee -a "$summary"

step "installing on a simulated gallery (scripts/install-report.sh): calibrate → scan → register → bake → what a visitor sees"
run_report install "${small_room[@]}" --poses 6
printf '%-28s calibration %.3f px, scan coverage %.1f%% / depth RMS %.3f mm / %.1f s; visitor view %.1f dB, texture %.2f mm from its place; lamp %.2f deg\n' \
    "install (640x360 room)" "$(jq .calibration_rms_px "$report")" \
    "$(jq '.scan_coverage * 100' "$report")" "$(jq .depth_rms_mm "$report")" \
    "$(jq .scan_seconds "$report")" "$(jq .psnr "$report")" \
    "$(jq .misregistration_mm "$report")" "$(jq .lamp_error_deg "$report")" \
    | tee -a "$summary"

step "measuring the light on a stained gallery (scripts/radiometry-report.sh): flat fields → vpe radiometry → bake → what the camera sees"
run_report radiometry "${small_room[@]}"
printf '%-28s %.2f levels of 255 RMS against the target (assumed radiometry: %.2f); re-measured: %.2f; %.0f s\n' \
    "radiometry (640x360 room)" "$(jq .rms_levels "$report")" \
    "$(jq .baseline_rms_levels "$report")" \
    "$(jq .stability_levels "$report")" "$(jq .seconds "$report")" \
    | tee -a "$summary"

step "three projectors around the vase (scripts/multi-projector-report.sh): shares from the geometry → 8 visitors"
run_report multi-projector
printf '%-28s seam step %.2fx its surroundings (no blending %.2fx), worst view %.2f dB (one projector, front: %.2f), %.1f%% of what visitors see lit\n' \
    "three projectors" "$(jq .seam_step_ratio "$report")" \
    "$(jq .unblended_seam_step_ratio "$report")" \
    "$(jq .worst_psnr "$report")" \
    "$(jq .single_front_psnr "$report")" \
    "$(jq '.lit_share * 100' "$report")" | tee -a "$summary"

if [[ -d "$data/synthrti" ]]; then
    for set in Single/Object1/material4:glossy-relief Multi/Object2/material1:shadowed-figures; do
        name=${set#*:}
        path="$data/synthrti/${set%%:*}"
        step "SynthRTI ${set%%:*} ($name)"
        fit_and_score "synthrti-$name" "$path/Dome" "$path/Test"
        rows=()
        prediction_rows "$out/synthrti-$name" "$path/Test" srgb .jpg image01 image06 image11 image16
        sheet 3 "$out/synthrti-$name/contact-sheet.png" "${rows[@]}"
    done
else
    echo "(SynthRTI not found under $data: skipping the real-capture part)" | tee -a "$summary"
fi
if [[ -d "$data/loewenkopf" ]]; then
    step "loewenkopf: a real photograph set, normals by photometric stereo"
    mkdir -p "$out/loewenkopf"
    "$vpe" fit "$data/loewenkopf" --out "$out/loewenkopf/paper.exr" --json > "$out/loewenkopf/fit.json"
    echo "loewenkopf                   fitted with photometric-stereo normals" | tee -a "$summary"
fi
rm -rf "$out"/*/tiles

cat >&2 <<TEXT

Demo finished in $(( $(date +%s) - started )) s. Pictures in $out:
  synthetic-bizen/contact-sheet.png   held-out lights: truth | paper model | extended model;
                                      last row: fit RMS map, normal map, material labels
  synthetic-bizen/sweep/sweep.svg     the paper's Fig. 6: held-out RMS vs M for five λ
  synthetic-bizen/capture/            the rendered capture (train/, test/, truth/)
  synthetic-bizen/texture/contact-sheet.png
                                      the texture stage: average, regions, source and quilted
                                      regions and the composed texture under one light
  synthetic-bizen/texture/weights.png the weight maps (grey per region, then colour-coded)
  synthetic-bizen/projection/contact-sheet.png
                                      a light moving around the vase: the projector frame,
                                      what a visitor would see, and the material itself
  synthetic-bizen/projection/visitor.mp4
                                      the same, animated: one turn of the light in 4 s, what a
                                      visitor sees (left) next to the material itself (right)
  synthetic-bizen/projection/scene.vpeb
                                      the device bundle (vpe info: info.txt)
  synthetic-bizen/player/contact-sheet.png
                                      the device program (vpe-player, OpenGL ES headless)
                                      playing the bundle along its idle path: 16 of 32 frames;
                                      frames/*.png, the animation's frames in order;
                                      unpaced.json (speed), fidelity.txt (GPU vs exact)
  synthetic-bizen/transfer/transfer-fidelity.md
                                      the true material vs the pipeline's rendering on the vase
                                      under 8 new lights and views (docs/transfer-fidelity.md);
                                      transfer-fidelity/contact-sheet.png: truth | pipeline |
                                      difference | without relief
  install/                            vpe installed on a simulated gallery (docs/install.md):
                                      procam-poses.png (the calibration's corners),
                                      scan-true/contact-sheet.png (the scan), check/visitor-check.png
                                      (what a visitor sees of the measured bundle vs the truth),
                                      install.json (the figures), room/ (the captures)
  radiometry/                         the light measured on a stained gallery (docs/radiometry.md):
                                      radiometry1/contact-sheet.png (F, albedo, floor, curves),
                                      check/light-check.png (target | measured | assumed),
                                      radiometry.json (the figures)
  multi-projector/                    three projectors around the vase (docs/multi-projector.md):
                                      shares.png (each one's share, the surface's reach),
                                      views.png (8 visitors: truth | show | light | reach),
                                      multi-projector.json (the figures)
  synthrti-*/contact-sheet.png        the same comparison on SynthRTI (when present)
  */paper.preview.png                 each model relit head-on and from three 45° lights
  summary.txt                         the figures above
TEXT
