#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The seam figure of docs/seams.md, written to docs/seams/ (or $1): the demo's synthetic Bizen
# capture fitted and segmented as the demo does, then quilted for the built-in vase at
# --size auto twice — tiling in u (--wrap on) and not (--wrap off). For each: every region map
# relit and laid twice side by side, cut around where the copies meet (u = 1 | 0, the seam on
# the vase); the vase baked with a projector and a viewer behind it, where the seam is, and its
# material rendered there; and vpe_seam_figure's numbers and plots — the step across the seam
# against the interior neighbour steps, on the maps and on the rendered frames.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test
source scripts/lib/pictures.sh
source scripts/lib/vpe.sh

out=$(realpath -m "${1:-docs/seams}")
build_vpe
cmake --build --preset release --target vpe_seam_figure -j "$(nproc)" >/dev/null
figure=$(realpath build/release/tests/benchmarks/vpe_seam_figure)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out" "$work/tiles"

echo "== the demo's capture, fit and regions" >&2
"$vpe" synth --out "$work/capture" --size 160 --noise camera
"$vpe" fit "$work/capture/train" --out "$work/model.exr" --no-preview
"$vpe" segment "$work/model.exr" --out "$work/labels.png" --auto auto

# A projector and a viewer behind the vase (the demo's, turned half a turn about its axis):
# the seam u = 0 | 1 faces them. OpenCV's FileStorage YAML, as procam-calibration writes it:
# x_proj = R·X + T, the projector at (0, 0.075, −0.6) looking along +z, 30° vertical field.
cat > "$work/behind.yml" <<'YAML'
%YAML:1.0
---
proj_width: 1920
proj_height: 1080
length_unit: m
proj_K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 2015.2968, 0., 959.5, 0., 2015.2968, 539.5, 0., 0., 1. ]
R: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ -1., 0., 0., 0., -1., 0., 0., 0., 1. ]
T: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ 0., 0.075, 0.6 ]
YAML

light=0.45,0.35,1
for wrap in on off; do
    name=$([[ $wrap == on ]] && echo tiled || echo plain)
    echo "== quilt --size auto --wrap $wrap" >&2
    "$vpe" quilt "$work/model.exr" --labels "$work/labels.png" --size auto --wrap "$wrap" \
        --out "$work/quilt-$wrap" --json > "$work/quilt-$wrap.json"
    width=$(jq .width "$work/quilt-$wrap.json")
    height=$(jq .height "$work/quilt-$wrap.json")
    for region in 0 1; do
        "$vpe" relight "$work/quilt-$wrap/region$region.exr" --light "$light" \
            --out "$work/region$region-$wrap.png"
        # Two copies side by side, cut 96 texels either side of where they meet.
        oiiotool "$work/region$region-$wrap.png" "$work/region$region-$wrap.png" --mosaic 2x1 \
            --cut "192x$height+$((width - 96))+0" -o "$work/seam$region-$wrap.png"
        tile "$work/seam$region-$wrap.png" "$work/tiles/$wrap-$region.png" \
            "region $region, $name: u = 1 | 0 in the middle" srgb 384
    done
    "$vpe" bake --quilt "$work/quilt-$wrap" --projector "$work/behind.yml" --viewer 0,0.075,-1 \
        --preset "region0=constant:value=1,constant:value=0" \
        --preset "region1=constant:value=0,constant:value=1" \
        --out "$work/scene-$wrap.vpeb" --json > "$work/bake-$wrap.json"
    for preset in region0 region1; do
        "$vpe" render "$work/scene-$wrap.vpeb" --weights "$preset" --light -0.3,0.35,-0.6 \
            --gain 0.5 --exposure 6 --view-fov 12 --out "$work/projector-$wrap-$preset.png" \
            --direct "$work/material-$wrap-$preset.png" > /dev/null
        tile "$work/material-$wrap-$preset.png" "$work/tiles/$wrap-vase-$preset.png" \
            "$name, ${preset/region/region }: the vase from behind, the seam in the middle" srgb 480
    done
done
sheet 4 "$out/seam-maps.png" "$work"/tiles/{off-0,off-1,on-0,on-1}.png
sheet 2 "$out/seam-vase.png" "$work"/tiles/{off-vase-region0,on-vase-region0,off-vase-region1,on-vase-region1}.png

echo "== the steps across the seam" >&2
# The frames' seam statistics render the first preset (region 0 alone) from the bundle's viewer.
"$figure" "$work/quilt-on" "$work/quilt-off" --out "$out" \
    --bundles "$work/scene-on.vpeb" "$work/scene-off.vpeb" | tee "$work/figure.txt" >&2
tail -1 "$work/figure.txt" > "$out/seam-steps.json"
for wrap in on off; do
    jq -c '{width, height, texel_mm, wrap_u, stretch, seams}' "$work/quilt-$wrap.json" \
        > "$out/quilt-$wrap.json"
done
echo "wrote $out: seam-maps.png, seam-vase.png, seam-steps-region*.svg, seam-steps.json, quilt-*.json" >&2
