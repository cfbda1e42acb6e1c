// SPDX-License-Identifier: MIT
// Robust Lambertian photometric stereo from the capture itself, for captures without a
// normal map. Shadows and highlights break the Lambertian assumption, so each pixel's fit
// starts from the samples between two luminance ranks (dropping the darkest and brightest),
// then reweights all unsaturated samples with Tukey's biweight (IRLS) around that start.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/normals/normal_map.h"

namespace vpe::normals {

struct PhotometricStereoOptions {
    double darkFraction = 0.3;    // share of darkest samples left out of the first fit
    double brightFraction = 0.1;  // share of brightest samples left out of the first fit
    int iterations = 5;           // IRLS rounds
    unsigned threads = 1;
    // W × H, nonzero where a normal is wanted (null: everywhere). Each pixel's estimate is its
    // own, so a normal estimated here is the one the whole map would hold.
    const std::vector<std::uint8_t>* pixels = nullptr;
};

NormalMap estimateNormals(const capture::Capture& capture, const PhotometricStereoOptions& options);

}  // namespace vpe::normals
