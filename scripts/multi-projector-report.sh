#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Several projectors on one object: three 1080p projectors around the vase,
# blended from the geometry, seen by visitors from 8 positions around it (docs/multi-projector.md).
#   vpe synth, vpe fit --model extended   the built-in synthetic Bizen capture and its model
#   vpe projector-ring --count 3          three projectors 120° apart, 0.6 m away, 15° up
#   vpe bake --projector ×3               one bundle each, with its share of the light
#   vpe show-check                        8 visitors around the vase: transfer PSNR against the
#                                         true material, the seam step, the lit share
# and, to compare: one projector in front (its front view), the same three without blending
# (each gives all the light) and with a hard edge (--blend-feather 0.5).
#   scripts/multi-projector-report.sh [--out DIR]
# The last line of stdout is one JSON object: seam_step_ratio (the worst view's), psnr_drop_db
# (the single projector's front view minus the worst view of the show), lit_share, and the
# baselines'.
set -euo pipefail
cd "$(dirname "$0")/.."
out=multi-projector-report
source scripts/lib/report.sh
report_options multi-projector-report out -- "$@"
source scripts/lib/pictures.sh
start_report

step "the synthetic Bizen capture and its extended model"
"$vpe" synth --out "$out/capture" --size 160 --noise camera >&2
"$vpe" fit "$out/capture/train" --out "$out/model.exr" --model extended --no-preview >&2

step "three projectors around the vase, and one in front"
"$vpe" projector-ring --count 3 --out "$out/ring" >&2
"$vpe" projector-ring --count 1 --out "$out/front" >&2
ring=("$out"/ring/projector{1,2,3}.yml)
bake_args=(--texture "$out/model.exr")
projector_args=()
for p in "${ring[@]}"; do projector_args+=(--projector "$p"); done
"$vpe" bake "${bake_args[@]}" "${projector_args[@]}" --out "$out/show" --json > "$out/show.json"
"$vpe" bake "${bake_args[@]}" "${projector_args[@]}" --blend-feather 0.5 --out "$out/hard" >&2
"$vpe" bake "${bake_args[@]}" --projector "$out/front/projector1.yml" --out "$out/front.vpeb" >&2
unblended=()
for i in 1 2 3; do
    "$vpe" bake "${bake_args[@]}" --projector "$out/ring/projector$i.yml" \
        --out "$out/alone$i.vpeb" 2> /dev/null
    unblended+=("$out/alone$i.vpeb")
done

step "visitors around the vase (vpe show-check, 8 views)"
"$vpe" show-check "$out/capture" "$out"/show/projector{1,2,3}.vpeb --out "$out/views" --json \
    > "$out/check.json"
"$vpe" show-check "$out/capture" "$out"/hard/projector{1,2,3}.vpeb --json > "$out/check-hard.json"
"$vpe" show-check "$out/capture" "${unblended[@]}" --json > "$out/check-unblended.json"
"$vpe" show-check "$out/capture" "$out/front.vpeb" --views 1 --out "$out/front-view" --json \
    > "$out/check-front.json"

step "pictures: share maps, the surface's reach, the views"
tiles="$out/tiles"
mkdir -p "$tiles"
for i in 1 2 3; do
    oiiotool "$out/show/projector$i-share.png" --ch Y,Y,Y -o "$tiles/share$i-rgb.png"
    tile "$tiles/share$i-rgb.png" "$tiles/share$i.png" "projector $i: its share" srgb 320
done
tile "$out/show/reach.png" "$tiles/reach.png" "reach: none|1|2|3 (texture space)" srgb 320
sheet 4 "$out/shares.png" "$tiles"/share{1,2,3}.png "$tiles/reach.png"
rows=()
for a in 0 45 90 135 180 225 270 315; do
    tile "$out/views/view$a-truth.png" "$tiles/$a-truth.png" "truth, ${a}°" srgb 240
    tile "$out/views/view$a-show.png" "$tiles/$a-show.png" "3 projectors, ${a}°" srgb 240
    tile "$out/views/view$a-light.png" "$tiles/$a-light.png" "light / material, ${a}°" srgb 240
    tile "$out/views/view$a-reach.png" "$tiles/$a-reach.png" "reach, ${a}°" srgb 240
    rows+=("$tiles/$a-truth.png" "$tiles/$a-show.png" "$tiles/$a-light.png" "$tiles/$a-reach.png")
done
sheet 4 "$out/views.png" "${rows[@]}"
rm -rf "$tiles"

front=$(jq .worst_psnr "$out/check-front.json")
jq -n --slurpfile show "$out/check.json" --slurpfile hard "$out/check-hard.json" \
    --slurpfile none "$out/check-unblended.json" --slurpfile bake "$out/show.json" \
    --argjson front "$front" \
    '{seam_step_ratio: ($show[0].seam_step_ratio * 1000 | round / 1000),
      psnr_drop_db: (($front - $show[0].worst_psnr) * 100 | round / 100),
      lit_share: ($show[0].lit_share * 10000 | round / 10000),
      mean_psnr: ($show[0].mean_psnr * 100 | round / 100),
      worst_psnr: ($show[0].worst_psnr * 100 | round / 100),
      single_front_psnr: ($front * 100 | round / 100),
      hard_edge_seam_step_ratio: ($hard[0].seam_step_ratio * 1000 | round / 1000),
      unblended_seam_step_ratio: ($none[0].seam_step_ratio * 1000 | round / 1000),
      unblended_worst_psnr: ($none[0].worst_psnr * 100 | round / 100),
      surface_unreached_share: ($bake[0].unreached_share * 10000 | round / 10000),
      surface_overlap_share: ($bake[0].overlap_share * 10000 | round / 10000)}' -c
