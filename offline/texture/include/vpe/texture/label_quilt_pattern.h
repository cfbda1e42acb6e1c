// SPDX-License-Identifier: MIT
// A global pattern synthesized from the source's label map itself: Image Quilting (the quilter
// `vpe quilt` uses) of the map, so the output's streaks are the source's own, cut into blocks
// and stitched again. Its local statistics (widths, edges) are the source's; whether its long
// lines survive is what it shows — the paper expects local synthesis to lose them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace vpe::texture {

struct LabelQuiltParameters {
    std::filesystem::path labels;  // `from=`: a label image (vpe segment's labels.png)
    int region = 0;                // the label the weight is 1 on
    std::optional<int> block;      // block side, pixels; default 4 × the region's median width
    std::optional<int> overlap;    // default block / 6 (at least 2)
    double softness = 2;           // edge ramp width, pixels (0: hard)
    std::uint64_t seed = 1;
};

// The label map quilted to width × height, as a weight: 1 inside the region, 0 outside, a
// linear ramp `softness` wide across its edges. The quilt runs on one channel, the signed
// distance to the region's edge (positive inside, clipped at ± the block's half side), so
// blocks are chosen to continue the bands they overlap. Throws InputError naming the label
// image when it cannot be quilted (no region, blocks larger than the labelled area).
std::vector<float> quiltLabelPattern(const LabelQuiltParameters& parameters, int width, int height);

}  // namespace vpe::texture
