// SPDX-License-Identifier: MIT
// Segmentation of a model into reflectance regions, the first step of texture synthesis:
// seeded (the paper's method: a seed per region, nearest average colour) or automatic
// (k-means on the appearance features, K given or chosen), then tiny islands removed.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/segment/average_appearance.h"
#include "vpe/segment/label_map.h"

namespace vpe::segment {

struct SegmentOptions {
    std::vector<PixelSeed> seeds;  // seeded when not empty
    SeedSpace seedSpace = SeedSpace::kAppearance;
    int clusters = 0;  // automatic: K, or 0 to choose it in [minClusters, maxClusters]
    int minClusters = 2;
    int maxClusters = 8;
    // Regions smaller than this many pixels are merged into their surroundings; negative:
    // kDefaultIslandShare of the valid pixels.
    long minIsland = -1;
    std::uint64_t seed = 1;
    unsigned threads = 1;
};

// A region smaller than 0.2% of the picture is noise, not a material a texture could be
// quilted from (a 128 × 128 model: 33 pixels, a 6 × 6 patch).
inline constexpr double kDefaultIslandShare = 0.002;

struct SegmentResult {
    LabelMap map;
    std::size_t minIsland = 0;
    std::size_t islandsMerged = 0;
    // Automatic segmentation: the K used, and the candidates' silhouettes when it was chosen.
    int clusters = 0;
    std::vector<int> candidates;
    std::vector<double> silhouettes;
};

// Throws InputError for seeds outside the model or on pixels without a valid fit, and for K
// outside [1, LabelMap::kMaxLabels] or above the number of valid pixels.
SegmentResult segmentAppearance(const Appearance& appearance, const SegmentOptions& options);

}  // namespace vpe::segment
