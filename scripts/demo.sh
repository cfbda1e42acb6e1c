#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The demo: everything built so far, end to end, writing pictures to demo-output/ (or $1).
# Fits the paper's Fourier BRDF and vpe's extended model to real captures, scores them on
# held-out lights, reproduces the paper's Fig. 6, and lays the results out as contact
# sheets. Installs missing Debian packages itself.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh

out=$(realpath -m "${1:-demo-output}")
data=${VPE_DATA:-$(realpath -m ../shared/data)}
cmake --preset release >/dev/null
cmake --build --preset release --target vpe -j "$(nproc)"
vpe=build/release/offline/vpe
mkdir -p "$out"
summary="$out/summary.txt"
: > "$summary"
psnr() { sed -n 's/.*"psnr":\([0-9.]*\).*/\1/p' | tail -1; }

# truth | paper model | extended model for four held-out lights, one row per light.
contact_sheet() {  # sheet test-folder paper-predictions extended-predictions
    local sheet=$1 test=$2 paper=$3 extended=$4 tiles=()
    for image in image01 image06 image11 image16; do
        tiles+=("$test/$image.jpg" "$paper/$image.png" "$extended/$image.png")
    done
    oiiotool "${tiles[@]}" --mosaic:pad=4 3x4 -o "$sheet"
}

fit_and_score() {  # name capture-folder
    local name=$1 set=$2 dir="$out/$1"
    mkdir -p "$dir"
    echo "== $name: paper model (M = 10, λ = 3.14) and extended model" >&2
    "$vpe" fit "$set/Dome" --out "$dir/paper.exr" --json > "$dir/paper-fit.json"
    "$vpe" eval "$dir/paper.exr" "$set/Test" --predictions "$dir/paper-test" --json > "$dir/paper-eval.json"
    "$vpe" fit "$set/Dome" --out "$dir/extended.exr" --model extended --json > "$dir/extended-fit.json"
    "$vpe" eval "$dir/extended.exr" "$set/Test" --predictions "$dir/extended-test" --json > "$dir/extended-eval.json"
    contact_sheet "$dir/contact-sheet.png" "$set/Test" "$dir/paper-test" "$dir/extended-test"
    printf '%-28s held-out PSNR: paper %6.2f dB, extended %6.2f dB\n' "$name" \
        "$(psnr < "$dir/paper-eval.json")" "$(psnr < "$dir/extended-eval.json")" | tee -a "$summary"
}

if [[ -d "$data/synthrti" ]]; then
    fit_and_score glossy-relief "$data/synthrti/Single/Object1/material4"
    fit_and_score shadowed-figures "$data/synthrti/Multi/Object2/material1"
    echo "== the paper's Fig. 6 on SynthRTI Single/Object1/material4" >&2
    mkdir -p "$out/sweep"
    "$vpe" sweep "$data/synthrti/Single/Object1/material4/Dome" \
        "$data/synthrti/Single/Object1/material4/Test" --out "$out/sweep" | tee "$out/sweep/table.txt"
else
    echo "vpe demo: SynthRTI captures not found under $data (set VPE_DATA)" >&2
fi
if [[ -d "$data/loewenkopf" ]]; then
    echo "== loewenkopf: a real photograph set, normals by photometric stereo" >&2
    mkdir -p "$out/loewenkopf"
    "$vpe" fit "$data/loewenkopf" --out "$out/loewenkopf/paper.exr" --json > "$out/loewenkopf/fit.json"
    echo "loewenkopf                   fitted with photometric-stereo normals: $out/loewenkopf/paper.preview.png" | tee -a "$summary"
fi
if [[ ! -s "$summary" ]]; then
    echo "vpe demo: no capture to run on: put the captures in ../shared/data or set VPE_DATA" >&2
    exit 1
fi

cat >&2 <<TEXT

Pictures written to $out:
  */contact-sheet.png        held-out lights: truth | paper model | extended model (rows: lights)
  */paper.preview.png        each model relit head-on and from three 45° lights
  */paper-test, */extended-test   every held-out prediction
  sweep/sweep.svg, sweep.csv the paper's Fig. 6: RMS vs harmonics M for five λ
  summary.txt                the figures above
TEXT
