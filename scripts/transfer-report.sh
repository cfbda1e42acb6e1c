#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates docs/transfer-fidelity.md and docs/transfer-fidelity/contact-sheet.png: how much
# the screen vase, seen by a visitor, looks like the captured material. The true material of
# the synthetic Bizen capture is rendered on the vase and compared with what the pipeline
# renders there from the fitted model (`vpe transfer`), for the paper's model and the extended
# model's transferable part, with the relief carried as a detail normal map, left out, or left
# to the coefficients (fitted against the macro shape).
#   scripts/transfer-report.sh [--capture DIR] [--size N] [--out FOLDER]
# --capture reuses a `vpe synth` capture (the demo's); --out writes FOLDER/transfer-fidelity.md
# and FOLDER/transfer-fidelity/ instead of docs/. The last line of stdout is one JSON object
# with the default configuration's (extended model, relief carried) "psnr" and "ssim".
set -euo pipefail
cd "$(dirname "$0")/.."
capture="" size=160 out=docs
while (($#)); do
    case $1 in
        --capture) capture=$(realpath -m "$2"); shift 2 ;;
        --size) size=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        *) echo "transfer-report: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
out=$(realpath -m "$out")
scripts/install-deps.sh
source scripts/lib/pictures.sh
source scripts/lib/vpe.sh
build_vpe
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [[ -n "$capture" ]]; then
    size=$(json_field size < "$capture/truth/synth.json")
else
    echo "== the synthetic Bizen capture (vpe synth --size $size --noise camera)" >&2
    capture="$work/capture"
    "$vpe" synth --out "$capture" --size "$size" --noise camera >&2
fi

# One row per configuration: model, relief handling, held-out PSNR on the capture, and the
# transfer's mean PSNR, worst view, mean SSIM, relief error.
rows="$work/rows.txt"
: > "$rows"
declare -A heldout
for model in paper extended; do
    echo "== $model model: fit (relief as a detail map, and in the coefficients), bake, transfer" >&2
    "$vpe" fit "$capture/train" --out "$work/$model.exr" --model "$model" --no-preview >&2
    "$vpe" fit "$capture/train" --out "$work/$model-coefficients.exr" --model "$model" \
        --relief coefficients --no-preview >&2
    heldout[$model]=$("$vpe" eval "$work/$model.exr" "$capture/test" --json 2>/dev/null | json_field psnr)
    heldout[$model-coefficients]=$("$vpe" eval "$work/$model-coefficients.exr" "$capture/test" --json \
        2>/dev/null | json_field psnr)
    "$vpe" bake --texture "$work/$model.exr" --out "$work/$model-relief.vpeb" >&2
    "$vpe" bake --texture "$work/$model.exr" --relief off --out "$work/$model-flat.vpeb" >&2
    "$vpe" bake --texture "$work/$model-coefficients.exr" --out "$work/$model-coefficients.vpeb" >&2
    for config in "relief detail-map relief" "flat none flat" "coefficients in-coefficients coefficients" \
                  "relief true-relief relief --true-relief"; do
        read -r bundle label pictures flag <<< "$config"
        fitted=$model
        [[ "$bundle" == coefficients ]] && fitted=$model-coefficients
        report=$("$vpe" transfer "$capture" "$work/$model-$bundle.vpeb" ${flag:-} \
            --out "$work/pictures-$model-$label" --json 2>/dev/null | tail -1)
        echo "$report" > "$work/$model-$label.json"
        printf '%s %s %s %s %s %s %s\n' "$model" "$label" "${heldout[$fitted]}" \
            "$(json_field psnr <<< "$report")" "$(json_field worst_psnr <<< "$report")" \
            "$(json_field ssim <<< "$report")" "$(json_field relief_error_degrees <<< "$report")" \
            | tee -a "$rows" >&2
    done
done

# Per view, the default configuration (extended, relief carried) and the same without relief.
views="$work/views.txt"
sed 's/},{/}\n{/g' "$work/extended-detail-map.json" | sed -n 's/.*"name":"\([a-z-]*\)","psnr":\([0-9.]*\),"ssim":\([0-9.]*\).*/\1 \2 \3/p' > "$views"
sed 's/},{/}\n{/g' "$work/extended-none.json" | sed -n 's/.*"name":"\([a-z-]*\)","psnr":\([0-9.]*\),"ssim":\([0-9.]*\).*/\2 \3/p' \
    | paste -d' ' "$views" - > "$work/views-both.txt"
sed 's/},{/}\n{/g' "$work/paper-detail-map.json" | sed -n 's/.*"name":"\([a-z-]*\)","psnr":\([0-9.]*\),"ssim":\([0-9.]*\).*/\2 \3/p' \
    | paste -d' ' "$work/views-both.txt" - > "$work/views-all.txt"

# The contact sheet: per view, truth | pipeline | difference × 4 | pipeline without relief.
mkdir -p "$work/tiles"
tiles=()
while read -r view _; do
    tile "$work/pictures-extended-detail-map/$view-truth.png" "$work/tiles/$view-1.png" "$view: truth" srgb 200
    tile "$work/pictures-extended-detail-map/$view-pipeline.png" "$work/tiles/$view-2.png" "pipeline" srgb 200
    tile "$work/pictures-extended-detail-map/$view-difference.png" "$work/tiles/$view-3.png" "difference x4" srgb 200
    tile "$work/pictures-extended-none/$view-pipeline.png" "$work/tiles/$view-4.png" "without relief" srgb 200
    tiles+=("$work/tiles/$view-1.png" "$work/tiles/$view-2.png" "$work/tiles/$view-3.png" "$work/tiles/$view-4.png")
done < "$views"
mkdir -p "$work/out/transfer-fidelity"
sheet 4 "$work/out/transfer-fidelity/contact-sheet.png" "${tiles[@]}"

default_psnr=$(awk '$1 == "extended" && $2 == "detail-map" { printf "%.2f", $4 }' "$rows")
default_ssim=$(awk '$1 == "extended" && $2 == "detail-map" { printf "%.4f", $6 }' "$rows")
default_worst=$(awk '$1 == "extended" && $2 == "detail-map" { printf "%.2f", $5 }' "$rows")
{
    echo "# Transfer fidelity: what a visitor sees against the captured material"
    echo
    echo "Generated by \`scripts/transfer-report.sh\` on $(date -u +%Y-%m-%d) ($(nproc) cores): the"
    echo "synthetic Bizen capture (\`vpe synth --size $size --noise camera\`: paper rig, 330 training"
    echo "lights, 16-bit linear images with shot and read noise, relief shadows) fitted, baked on the"
    echo "built-in vase, and scored by \`vpe transfer\`."
    echo
    echo "## Method"
    echo
    echo "- **The truth on the vase.** \`vpe synth\` knows its material per capture pixel: GGX +"
    echo "  Lambert parameters (\`truth/parameters.exr\`) and the relief, its true normals"
    echo "  (\`truth/normals.exr\`) against the smooth surface of revolution's (\`truth/macro-normals.exr\`)."
    echo "  \`vpe transfer\` lays them on the bundle's mesh through the same texture layout as the fitted"
    echo "  model — texel (x, y) is capture pixel (x, y), no quilting — and renders them directly: the"
    echo "  microfacet radiance with the relief's normal (applied as the pipeline applies its own:"
    echo "  \`proto/detail_normal.h\`), the same horizon factor — the smooth terminator of"
    echo "  \`proto/surface_horizon.h\`, which came with the corrected terminator, before this measurement — and no"
    echo "  cast shadows (the virtual light casts none)."
    echo "- **The pipeline.** \`vpe fit\` (paper or extended model), \`vpe bake --texture MODEL.exr\` (one"
    echo "  region, low-rank rank 12, half floats: the device's data), and the CPU reference's direct"
    echo "  view of the material on the vase (\`vpe render --direct\`'s), same camera, 480 × 360, 20°."
    echo "- **Views the capture never had** (the paper rig lit from −10° to 50° of elevation within"
    echo "  ±81° of the camera): \`key\` (inside that range, a control), \`grazing-side\` (light 5° above"
    echo "  the horizon, from the side), \`grazing-top\` (from 80° above), \`below\` (from 50° below),"
    echo "  \`side-view\` (viewer at the side, light from the front), \`back\` (viewer behind the vase, over"
    echo "  the texture's seam), \`backlit\` (light behind the vase's side), \`above\` (viewer 55° up, light"
    echo "  low from the left). Viewer and light 4 vase heights from its centre."
    echo "- **Metric.** Both pictures as people see them: radiance × one exposure (the truth's 99th"
    echo "  percentile at 0.8), sRGB-encoded, 8-bit. PSNR over the vase's pixels that either picture"
    echo "  lights; SSIM (Gaussian window 11 × 11, σ = 1.5, K1 = 0.01, K2 = 0.03, L = 255) computed on each"
    echo "  of R, G and B, averaged over the same pixels (\`offline/image/image_metrics.*\`). Per view,"
    echo "  then the mean over the eight views."
    echo "- **Relief.** \`detail map\`: the fit uses the per-pixel normals and writes the relief as a"
    echo "  detail normal map relative to the macro shape (a local quadratic regression of the normals,"
    echo "  σ = 1/8 of the image), which the bake carries into the bundle and both renderers apply"
    echo "  through the mesh's tangent frame. \`none\`: the same fit baked without it (\`--relief off\`,"
    echo "  what vpe did before). \`in coefficients\`: the fit uses the macro normals, so the"
    echo "  coefficients absorb the relief's shading as far as a function of (θd, θs) can"
    echo "  (\`vpe fit --relief coefficients\`). \`true relief\` is a diagnostic: the detail-map bundle"
    echo "  rendered with the truth's relief instead of its own (\`vpe transfer --true-relief\`)."
    echo
    echo "## Results"
    echo
    echo "| model | relief | held-out PSNR on the capture (dB) | transfer PSNR, mean of views (dB) | worst view (dB) | mean SSIM | relief error (°) |"
    echo "|---|---|---|---|---|---|---|"
    awk '{ label = $2; gsub("-", " ", label);
           bold = ($1 == "extended" && $2 == "detail-map") ? "**" : "";
           printf "| %s | %s%s%s | %.2f | %s%.2f%s | %.2f | %s%.4f%s | %.2f |\n",
                  $1, bold, label, bold, $3, bold, $4, bold, $5, bold, $6, bold, $7 }' "$rows"
    echo
    echo "The default configuration — the extended model's transferable part with its relief carried"
    echo "as a detail normal map — measures **${default_psnr} dB** (worst view ${default_worst} dB) and"
    echo "SSIM **${default_ssim}**. Per view (PSNR dB / SSIM):"
    echo
    echo "| view | extended, detail map | extended, no relief | paper, detail map |"
    echo "|---|---|---|---|"
    awk '{ printf "| %s | %.2f / %.4f | %.2f / %.4f | %.2f / %.4f |\n", $1, $2, $3, $4, $5, $6, $7 }' \
        "$work/views-all.txt"
    echo
    echo "![truth | pipeline | difference × 4 | pipeline without relief, per view](transfer-fidelity/contact-sheet.png)"
    echo
    echo "## What the numbers say"
    echo
    echo "- **Carry the relief as a detail map.** Without it the vase loses the relief's shading"
    echo "  under every light, and the coefficients, fitted relative to other normals than the ones"
    echo "  rendered, put the wrong lobe in the wrong place. Fitting against the macro normals instead"
    echo "  does not recover it: per texel, the relief is a tilt of the normal, and a function of the"
    echo "  macro normal's (θd, θs) can only follow it under the lights it was fitted to. The detail"
    echo "  map is consistent by construction: the coefficients are fitted relative to the normals they"
    echo "  are rendered with."
    echo "- **The extended model's transferable part** beats the paper's: the paper's fit absorbs the"
    echo "  relief's cast shadows into the material (they darken it wherever the capture was shadowed),"
    echo "  the extended model explains them with its capture-specific transport and leaves the"
    echo "  material clean."
    echo "- **What remains** is the model family's: \`backlit\` (light from behind, viewer in front) is"
    echo "  specular reflection at grazing angles, where the true glaze's Fresnel term makes it many"
    echo "  times brighter; f(θd, θs) = Lambert(θd) + g(θs) has one specular lobe whatever the"
    echo "  incidence, fitted to lights that never grazed. The relief's estimate costs the difference"
    echo "  between the \`detail map\` and \`true relief\` rows."
} > "$work/out/transfer-fidelity.md"
mkdir -p "$out/transfer-fidelity"
cp "$work/out/transfer-fidelity.md" "$out/"
cp "$work/out/transfer-fidelity/contact-sheet.png" "$out/transfer-fidelity/"
echo "wrote $out/transfer-fidelity.md" >&2
printf '{"configuration":"extended, relief as a detail map","size":%s,"worst_psnr":%s,"ssim":%s,"psnr":%s}\n' \
    "$size" "$default_worst" "$default_ssim" "$default_psnr"
