# SPDX-License-Identifier: MIT
# Picture helpers for the scripts (sourced): labelled tiles and contact sheets with oiiotool.
# Labels need a font; Debian's fonts-dejavu-core provides it.

picture_font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf

# tile IN OUT LABEL [linear|srgb] [SIZE]: IN resized to SIZE pixels wide (default 192),
# sRGB-encoded if it holds linear values, with LABEL written in its top-left corner.
tile() {
    local in=$1 out=$2 label=$3 encoding=${4:-srgb} size=${5:-192}
    local convert=()
    [[ "$encoding" == linear ]] && convert=(--colorconvert linear sRGB)
    oiiotool "$in" --ch R,G,B "${convert[@]}" --resize "${size}x0" \
        --text:x=4:y=15:size=13:color=1,1,0.3:font="$picture_font" "$label" \
        -d uint8 -o "$out"
}

# sheet COLUMNS OUT TILE...: the tiles row by row, 4 pixels apart.
sheet() {
    local columns=$1 out=$2
    shift 2
    local rows=$(( ($# + columns - 1) / columns ))
    oiiotool "$@" --mosaic:pad=4 "${columns}x${rows}" -d uint8 -o "$out"
}

# channels_picture MODEL.exr CHANNELS OUT SCALE OFFSET: a model channel triple as a picture,
# value * SCALE + OFFSET (e.g. normals: 0.5, 0.5; RMS maps: 10, 0).
channels_picture() {
    local model=$1 channels=$2 out=$3 scale=$4 offset=$5
    oiiotool "$model" --ch "$channels" --mulc "$scale" --addc "$offset" --clamp:min=0:max=1 \
        -d uint8 -o "$out"
}
