// SPDX-License-Identifier: MIT
// importGrayCodeCapture: a capture of OpenCV's structured_light GrayCodePattern, as
// kamino410/procam-calibration lays it out, turned into a vpe scan folder (proto/SCAN.md) that
// vpe calibrate and vpe scan read: its images copied under their own names, and a scan.json
// that declares the sequence they show.
//
// The layout: one folder per pose holding graycode_00.png, graycode_01.png, … (or .jpg, .jpeg,
// .tif, .tiff: one format per folder; 8-bit, or 16-bit PNG and TIFF): the column bits
// from the most significant, each pattern followed by its inverse, then the row bits likewise,
// then white and black. For a W × H projector and step k (one code = k × k projector pixels)
// that is 2·(⌈log2 ⌈W/k⌉⌉ + ⌈log2 ⌈H/k⌉⌉) + 2 images.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vpe/proto/scan_manifest.h"

namespace vpe::structured_light {

struct GrayCodeProjector {
    int width = 0, height = 0;  // the projector's pixels the patterns were made for
    int codeStep = 1;           // projector pixels per code along each axis
};

// The image names of a GrayCodePattern capture ("graycode_07.png") and the pattern each shows,
// in the tool's order. Throws InputError "--projector …" when the size and step make no
// sequence.
std::vector<proto::ScanImage> grayCodeImages(const GrayCodeProjector& projector);

// Checks the capture folder — exactly the images the sequence needs (none missing, none extra),
// all of one format (extension), each an 8- or 16-bit integer image that OpenImageIO can read,
// all of one size and depth — and writes the scan folder `into` (which must not exist yet: the
// caller writes it beside its final place). Throws InputError naming the file and the problem.
proto::ScanManifest importGrayCodeCapture(const std::filesystem::path& capture,
                                          const GrayCodeProjector& projector,
                                          const std::filesystem::path& into);

}  // namespace vpe::structured_light
