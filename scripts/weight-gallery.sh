#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates the pictures and figures of docs/compose.md: every weight-map kind drawn by
# `vpe weights --raw` (docs/compose/kinds.png), the hidasuki stroke generator's parameters one
# at a time (docs/compose/strokes.png), and strokes defaulted from a source's own labels — the
# built-in synthetic capture at the demo's sizes — next to those labels, with the streak
# statistics of both (docs/compose/from-labels.png, and the table in docs/compose.md between
# its from-labels markers).
#   scripts/weight-gallery.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test  # jq reads the reports
source scripts/lib/vpe.sh
source scripts/lib/pictures.sh
doc=docs/compose.md
out=docs/compose
build_vpe
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

# pattern NAME SPEC [SIZE]: SPEC's raw weight as a labelled tile (the spec is the label).
tiles=()
pattern() {
    local name=$1 spec=$2 size=${3:-256x256}
    "$vpe" weights "$spec" --size "$size" --raw --out "$work/$name-full.png" 2>/dev/null
    # The picture is the grey tile, then the colour tile: keep the grey one.
    local width=${size%x*} height=${size#*x}
    oiiotool "$work/$name-full.png" --cut "${width}x${height}+0+0" -o "$work/$name.png"
    tile "$work/$name.png" "$work/$name-tile.png" "${spec//$work\//}" srgb 256
    tiles+=("$work/$name-tile.png")
}

echo "== synthetic capture at the demo's sizes: synth 160², fit, segment" >&2
capture="$work/capture"
"$vpe" synth --out "$capture" --size 160 --noise camera >/dev/null
"$vpe" fit "$capture/train" --out "$work/model.exr" --no-preview >/dev/null 2>&1
"$vpe" segment "$work/model.exr" --out "$work/labels.png" --auto auto >/dev/null 2>&1
streaks=0  # labels are ordered by luminance: the red-brown streaks are the darker label

echo "== every kind" >&2
tiles=()
pattern image "image:$capture/truth/labels-preview.png"
pattern stripes "stripes:angle=30:period=48:sharpness=3"
pattern radial "radial:radius=110"
pattern noise "noise:scale=40:octaves=3"
pattern noise-sharp "noise:scale=40:sharpness=4"
pattern strokes "strokes:width=8"
pattern strokes-labels "strokes:from=$work/labels.png:region=$streaks"
pattern quilted "quilted:from=$work/labels.png:region=$streaks"
pattern constant "constant:value=0.5"
sheet 3 "$out/kinds.png" "${tiles[@]}"

echo "== stroke parameters" >&2
tiles=()
pattern s-default "strokes"
pattern s-width "strokes:width=4:coverage=0.15"
pattern s-spread "strokes:spread=0.6"
pattern s-wobble "strokes:wobble=0.5"
pattern s-length "strokes:length=80"
pattern s-bend0 "strokes:bend=0"
pattern s-bend40 "strokes:bend=40"
pattern s-soft "strokes:softness=12"
pattern s-angle "strokes:angle=30:angle-spread=30"
pattern s-coverage "strokes:coverage=0.5"
pattern s-count "strokes:count=3:width=20"
pattern s-nowrap "strokes:wrap=none"
sheet 4 "$out/strokes.png" "${tiles[@]}"

echo "== strokes from the source's labels, quilted and composed at 512²" >&2
"$vpe" quilt "$work/model.exr" --labels "$work/labels.png" --size 512x512 --out "$work/quilt" \
    >/dev/null 2>&1
entry="strokes:from=$work/labels.png:region=$streaks"
"$vpe" compose "$work/quilt" --out "$work/composed.exr" --weights "$entry,$entry:invert" \
    --weights-out "$work/weights.png" --json > "$work/compose.json" 2>/dev/null
light=0.45,0.35,1
"$vpe" relight "$work/model.exr" --light "$light" --out "$work/source-relit.png"
"$vpe" relight "$work/composed.exr" --light "$light" --out "$work/composed-relit.png"
oiiotool "$work/weights.png" --cut 512x512+0+0 -o "$work/streak-weight.png"
quilted="quilted:from=$work/labels.png:region=$streaks"
"$vpe" weights "$quilted" --raw --size 512x512 --out "$work/quilted-full.png" --json \
    > "$work/quilted.json" 2>/dev/null
oiiotool "$work/quilted-full.png" --cut 512x512+0+0 -o "$work/quilted.png"
# The source is 160² and the texture 512² at the same texel size: the source tiles are drawn
# at 160/512 of the texture tiles' width, so a streak is as wide in both.
tiles=()
tile "$work/source-relit.png" "$work/t1.png" "source 160²" srgb 120
tile "$work/labels-overlay.png" "$work/t2.png" "its regions" srgb 120
tile "$work/streak-weight.png" "$work/t3.png" "strokes from its labels, 512²" srgb 384
tile "$work/composed-relit.png" "$work/t4.png" "composed, same light" srgb 384
tile "$work/quilted.png" "$work/t5.png" "its labels quilted, 512²" srgb 384
# Pasted on a canvas rather than a mosaic (whose cells are all the largest tile's size).
# (--paste takes the foreground below the background on the stack, hence --swap.)
oiiotool --create 1288x384 3 \
    "$work/t1.png" --swap --paste +0+0 "$work/t2.png" --swap --paste +0+124 \
    "$work/t3.png" --swap --paste +124+0 "$work/t4.png" --swap --paste +512+0 \
    "$work/t5.png" --swap --paste +900+0 -d uint8 -o "$out/from-labels.png"

jq -rs '(.[0].strokes[0]) as $s | (.[1].quilted[0]) as $q |
    def r(x; f): x * f | round / f;
    def row(name; t): "| \(name) | \(r(t.coverage; 1000)) | \(r(t.width_quartile1; 10)) | \(r(t.width_median; 10)) | \(r(t.width_quartile3; 10)) | \(r(t.width_log_spread; 100)) |";
    "| streaks | coverage | width Q1 | median | Q3 | log spread |",
    "|---|---|---|---|---|---|",
    row("source labels (160², `vpe segment --auto auto`)"; $s.source),
    row("`strokes` weights, α ≥ ½ (512²)"; $s.composed),
    row("`quilted` weights, ≥ ½ (512²)"; $q.composed),
    "",
    "Strokes drawn with a fitted body width of \(r($s.width; 10)) texels and spread \(r($s.spread; 100)), length \($s.length | round) texels, softness \(r($s.softness; 10)) texels."' \
    <(tail -1 "$work/compose.json") <(tail -1 "$work/quilted.json") \
    > "$work/table.md"
# The table replaces what stands between the markers in the doc.
TABLE_FILE="$work/table.md" awk '
    /<!-- from-labels: begin/ { print; while ((getline line < ENVIRON["TABLE_FILE"]) > 0) print line; skip = 1; next }
    /<!-- from-labels: end/ { skip = 0 }
    !skip { print }' "$doc" > "$work/doc.md"
cp "$work/doc.md" "$doc"
echo "wrote $out/kinds.png, strokes.png, from-labels.png and the table in $doc" >&2
