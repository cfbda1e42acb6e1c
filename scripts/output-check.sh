#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Checks that a change leaves the pipeline's outputs as they were: runs the demo's chain on a
# small built-in capture (synth → fit paper and extended → eval → segment → quilt →
# quilt-quality → compose → relight → bake → info → render) with two `vpe` binaries, and
# compares every file they wrote. Files must be byte-identical, except:
#   - JSON reports, compared with their timing keys (seconds, *_s, *_ms, threads) removed;
#   - OpenEXR files, compared pixel for pixel and header for header, their DateTime aside.
# Prints one line per file that differs, then a summary; exit 0 when nothing differs, 1 when
# something does, 2 on bad arguments.
#   scripts/output-check.sh BEFORE_VPE AFTER_VPE [WORK_DIR]
# e.g. build a checkout of the old commit beside this one, then
#   scripts/output-check.sh ../old/build/release/offline/vpe build/release/offline/vpe
set -euo pipefail

if [[ $# -lt 2 || $# -gt 3 ]]; then
    echo "output-check: usage: scripts/output-check.sh BEFORE_VPE AFTER_VPE [WORK_DIR]" >&2
    exit 2
fi
for binary in "$1" "$2"; do
    [[ -x "$binary" ]] || { echo "output-check: $binary: not an executable vpe" >&2; exit 2; }
done
for tool in jq oiiotool; do
    command -v "$tool" >/dev/null || {
        echo "output-check: $tool is missing (scripts/install-deps.sh installs it)" >&2
        exit 2
    }
done
before_vpe=$(realpath "$1")
after_vpe=$(realpath "$2")
work=$(realpath -m "${3:-build/output-check}")

# The chain, as scripts/demo.sh runs it, at 96 × 96 texels so that it takes about a minute.
run_chain() {  # vpe out
    local vpe=$1 out=$2
    rm -rf "$out"
    mkdir -p "$out"
    (
        cd "$out"
        local strokes="strokes:from=labels.png:region=0"
        local stripes="stripes:angle=60:period=48:sharpness=4"
        "$vpe" synth --out capture --size 96 --noise camera > synth.txt
        "$vpe" fit capture/train --out paper.exr --json > paper-fit.json
        "$vpe" eval paper.exr capture/test --predictions paper-test --json > paper-eval.json
        "$vpe" fit capture/train --out extended.exr --model extended --json > extended-fit.json
        "$vpe" eval extended.exr capture/test --predictions extended-test --json \
            > extended-eval.json
        "$vpe" segment paper.exr --out labels.png --auto auto --truth capture/truth/labels.png \
            --average average.png --json > segment.json
        "$vpe" quilt paper.exr --labels labels.png --size auto --out quilt --json > quilt.json
        "$vpe" quilt-quality paper.exr --labels labels.png --quilt quilt --json \
            > quilt-quality.json
        "$vpe" compose quilt --out composed.exr --weights "$strokes,$strokes:invert" \
            --weights-out weights.png --json > compose.json
        "$vpe" relight paper.exr --light 0.45,0.35,1 --out source-relit.png
        "$vpe" relight composed.exr --light 0.45,0.35,1 --out composed-relit.png
        "$vpe" bake --quilt quilt --preset "strokes=$strokes,$strokes:invert" \
            --preset "stripes=$stripes,$stripes:invert" --out scene.vpeb --json > bake.json
        "$vpe" info scene.vpeb > info.txt
        "$vpe" render scene.vpeb --light 0.35,0.3,0.55 --gain 0.5 --exposure 6 --view-fov 12 \
            --out projector.png --simulate visitor.png --direct material.png --json > render.json
    ) 2> "$out.log" || { echo "output-check: $vpe failed; see $out.log" >&2; exit 1; }
}

without_timings='walk(if type == "object" then
    with_entries(select(.key | test("seconds|_s$|_ms$|threads") | not)) else . end)'
exr_header() { oiiotool --info -v "$1" 2>&1 | sed 1,2d | grep -v DateTime; }

same_file() {  # relative path
    local a="$work/before/$1" b="$work/after/$1"
    case "$1" in
        *.json) cmp -s <(jq -S "$without_timings" "$a") <(jq -S "$without_timings" "$b") ;;
        *.exr) oiiotool "$a" "$b" --diff >/dev/null 2>&1 &&
            cmp -s <(exr_header "$a") <(exr_header "$b") ;;
        *) cmp -s "$a" "$b" ;;
    esac
}

echo "output-check: the chain with $before_vpe" >&2
run_chain "$before_vpe" "$work/before"
echo "output-check: the chain with $after_vpe" >&2
run_chain "$after_vpe" "$work/after"

same=0
differ=0
while IFS= read -r file; do
    if [[ ! -e "$work/after/$file" ]]; then
        echo "missing after: $file"
        differ=$((differ + 1))
    elif same_file "$file"; then
        same=$((same + 1))
    else
        echo "differs: $file"
        differ=$((differ + 1))
    fi
done < <(cd "$work/before" && find . -type f | sed 's|^\./||' | sort)
while IFS= read -r file; do
    [[ -e "$work/before/$file" ]] || { echo "new after: $file"; differ=$((differ + 1)); }
done < <(cd "$work/after" && find . -type f | sed 's|^\./||' | sort)
echo "output-check: $same files the same, $differ differ (outputs in $work)"
[[ $differ -eq 0 ]]
