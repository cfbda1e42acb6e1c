#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The demo: the whole pipeline built so far, end to end, writing pictures to demo-output/
# (or $1). It renders the built-in synthetic Bizen capture, fits the paper's Fourier BRDF
# and vpe's extended model, scores them on held-out lights, reproduces the paper's Fig. 6,
# and lays the results out as contact sheets; then does the same on real captures when
# ../shared/data (or $VPE_DATA) has them. Installs missing Debian packages itself.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
source scripts/lib/pictures.sh
source scripts/lib/vpe.sh

started=$(date +%s)
out=$(realpath -m "${1:-demo-output}")
data=${VPE_DATA:-$(realpath -m ../shared/data)}
build_vpe
rm -rf "$out"
mkdir -p "$out"
summary="$out/summary.txt"
: > "$summary"
step() { printf '\n== %s\n' "$*" >&2; }

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
  synthrti-*/contact-sheet.png        the same comparison on SynthRTI (when present)
  */paper.preview.png                 each model relit head-on and from three 45° lights
  summary.txt                         the figures above
TEXT
