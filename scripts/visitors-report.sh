#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Many visitors at once (docs/visitors.md): three 1080p projectors around the Bizen vase, one
# virtual light from the front-left, each projector's frame drawn once, and 11 visitors standing
# at the same time — 8 around at eye height, 2 children, 1 looking down — each scored against
# the truth from where they stand, for each viewer model the frames can be drawn for:
#   bundle          the one eye each bundle carries (the device without a zone)
#   projector-side  per projector, an eye on that projector's side
#   zone            the visitors themselves as the viewing zone: each point drawn for the mean
#                   direction to those who see it (proto/viewing_zone.h)
#   ring            the bundles baked with vpe bake --viewing-zone 8: 8 eyes in a ring at the
#                   viewer's height, what an installer bakes without knowing where people stand
#   tracked         each visitor alone, the frames redrawn for them (the bound)
#   scripts/visitors-report.sh [--out DIR]
# The last line of stdout is one JSON object: per model worst_psnr, mean_psnr (eye and child
# height), highlight_share (mean share of true highlights seen within 2°), worst_highlight_share
# and above_psnr; seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
out=visitors-report
source scripts/lib/report.sh
report_options visitors-report out -- "$@"
source scripts/lib/pictures.sh
start_report

step "the synthetic Bizen capture and its extended model; three projectors around it"
"$vpe" synth --out "$out/capture" --size 160 --noise camera >&2
"$vpe" fit "$out/capture/train" --out "$out/model.exr" --model extended --no-preview >&2
"$vpe" projector-ring --count 3 --out "$out/ring" >&2
"$vpe" bake --texture "$out/model.exr" --projector "$out/ring/projector1.yml" \
    --projector "$out/ring/projector2.yml" --projector "$out/ring/projector3.yml" \
    --out "$out/show" >&2
"$vpe" bake --texture "$out/model.exr" --projector "$out/ring/projector1.yml" \
    --projector "$out/ring/projector2.yml" --projector "$out/ring/projector3.yml" \
    --viewing-zone 8 --out "$out/show-ring" >&2

step "11 visitors at once, per viewer model (vpe show-check --together)"
"$vpe" show-check "$out/capture" "$out"/show/projector{1,2,3}.vpeb \
    --together bundle,projector-side,zone,tracked --out "$out/views" --json > "$out/together.json"
"$vpe" show-check "$out/capture" "$out"/show-ring/projector{1,2,3}.vpeb \
    --together bundle --json > "$out/together-ring.json"

step "pictures: one row per visitor, truth | what they see | difference ×4"
for model in bundle zone; do
    rows=()
    for view in "$out"/views/"$model"-eye-{0,45,90,135,180,225,270,315}.png \
        "$out"/views/"$model"-child-*.png "$out"/views/"$model"-above-0.png; do
        rows+=("$view")
    done
    oiiotool "${rows[@]}" --mosaic "1x${#rows[@]}" --resize 50% -o "$out/$model-visitors.png"
done

jq -c --argjson seconds "$SECONDS" --slurpfile ring "$out/together-ring.json" '
    .models + {ring: $ring[0].models.bundle} | with_entries(.value |= {
        worst_psnr: (.worst_psnr * 100 | round / 100), mean_psnr: (.mean_psnr * 100 | round / 100),
        highlight_share: (.highlight_share * 1000 | round / 1000),
        worst_highlight_share: (.worst_highlight_share * 1000 | round / 1000),
        above_psnr: (.above.psnr * 100 | round / 100)}) + {seconds: $seconds}' "$out/together.json"
