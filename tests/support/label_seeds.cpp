// SPDX-License-Identifier: MIT
#include "support/label_seeds.h"

#include <algorithm>
#include <limits>

namespace vpe::testing {

std::vector<segment::PixelSeed> innermostPixels(const segment::LabelMap& map) {
    const int w = map.width, h = map.height;
    const auto at = [w](int x, int y) { return static_cast<std::size_t>(y) * w + x; };
    // Two-pass chamfer transform: distance to the nearest pixel of another label (unlabelled
    // pixels count as another label) or to outside the picture.
    std::vector<int> distance(map.values.size());
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::uint8_t label = map.values[at(x, y)];
            int d =
                label == segment::LabelMap::kNoLabel ? 0 : std::min({x + 1, y + 1, w - x, h - y});
            if (d > 0 && x > 0) {
                d = map.values[at(x - 1, y)] != label ? 1 : std::min(d, distance[at(x - 1, y)] + 1);
            }
            if (d > 0 && y > 0) {
                d = map.values[at(x, y - 1)] != label ? 1 : std::min(d, distance[at(x, y - 1)] + 1);
            }
            distance[at(x, y)] = d;
        }
    }
    for (int y = h - 1; y >= 0; --y) {
        for (int x = w - 1; x >= 0; --x) {
            const std::uint8_t label = map.values[at(x, y)];
            int& d = distance[at(x, y)];
            if (x + 1 < w) {
                d = map.values[at(x + 1, y)] != label ? std::min(d, 1)
                                                      : std::min(d, distance[at(x + 1, y)] + 1);
            }
            if (y + 1 < h) {
                d = map.values[at(x, y + 1)] != label ? std::min(d, 1)
                                                      : std::min(d, distance[at(x, y + 1)] + 1);
            }
        }
    }
    std::vector<int> best(segment::LabelMap::kMaxLabels, 0);
    std::vector<segment::PixelSeed> seeds(segment::LabelMap::kMaxLabels,
                                          segment::PixelSeed{-1, -1});
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::uint8_t label = map.values[at(x, y)];
            if (label != segment::LabelMap::kNoLabel && distance[at(x, y)] > best[label]) {
                best[label] = distance[at(x, y)];
                seeds[label] = segment::PixelSeed{x, y};
            }
        }
    }
    std::vector<segment::PixelSeed> present;
    for (const segment::PixelSeed& seed : seeds) {
        if (seed.x >= 0) {
            present.push_back(seed);
        }
    }
    return present;
}

std::string seedsArgument(const std::vector<segment::PixelSeed>& seeds) {
    std::string text;
    for (const segment::PixelSeed& seed : seeds) {
        text += (text.empty() ? "" : ";") + std::to_string(seed.x) + "," + std::to_string(seed.y);
    }
    return text;
}

}  // namespace vpe::testing
