// SPDX-License-Identifier: MIT
// How visible a texture's u seam is: the step between its last column and its first — where
// they meet on a screen object whose u wraps — against the steps between interior neighbour
// columns. A texture that tiles has a seam step like any interior one; one that does not has
// a step like two unrelated pixels'.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace vpe::quilt {

struct SeamStatistics {
    // Per neighbour-column pair x → x + 1 (x = 0 … W − 2): the mean over rows of
    // |c(x + 1, y) − c(x, y)| (Euclidean over the channels).
    std::vector<double> columnSteps;
    double seam = 0;  // the same for the pair W − 1 → 0
    // The distribution of columnSteps.
    double interiorMean = 0, interiorMedian = 0, interiorP95 = 0, interiorMax = 0;
    // Share of the interior column pairs whose step is below the seam's (1: above them all).
    double seamRank = 0;
    double ratio() const { return interiorMean > 0 ? seam / interiorMean : 0.0; }
};

// values: width × height texels of `channels` floats, row-major. Pixels whose `valid` is 0 (if
// given: one byte per texel) are left out of every pair they are part of. width ≥ 3.
SeamStatistics measureSeam(std::span<const float> values, int width, int height, int channels,
                           std::span<const unsigned char> valid = {});

// The statistics as the JSON reports name them (vpe quilt's "seams", the seam figure).
nlohmann::json seamJson(const SeamStatistics& s);

}  // namespace vpe::quilt
