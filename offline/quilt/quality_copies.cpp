// SPDX-License-Identifier: MIT
// The largest verbatim copy in a quilt: connected runs of one source offset (union-find).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "quality_metrics.h"

namespace vpe::quilt::metrics {

namespace {

std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

}  // namespace

void measureLargestCopy(const PositionMap& positions, RegionQuality& quality) {
    const std::size_t count = positions.sourceX.size();
    std::vector<std::size_t> parent(count);
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    auto sameOffset = [&](std::size_t p, std::size_t q, int dx, int dy) {
        return positions.known(p) && positions.known(q) &&
               positions.sourceX[q] - positions.sourceX[p] == dx &&
               positions.sourceY[q] - positions.sourceY[p] == dy;
    };
    for (int y = 0; y < positions.height; ++y) {
        for (int x = 0; x < positions.width; ++x) {
            const std::size_t p = positions.pixel(x, y);
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx < positions.width && y + dy < positions.height) {
                    const std::size_t q = positions.pixel(x + dx, y + dy);
                    if (sameOffset(p, q, dx, dy)) {
                        const std::size_t a = findRoot(parent, p), b = findRoot(parent, q);
                        parent[std::max(a, b)] = std::min(a, b);
                    }
                }
            }
        }
    }
    std::vector<std::size_t> size(count, 0);
    std::size_t bestRoot = 0;
    for (std::size_t p = 0; p < count; ++p) {
        if (!positions.known(p)) {
            continue;
        }
        const std::size_t root = findRoot(parent, p);
        if (++size[root] > quality.largestCopy) {
            quality.largestCopy = size[root];
            bestRoot = root;
        }
    }
    if (quality.largestCopy > 0) {
        const int x = static_cast<int>(bestRoot % static_cast<std::size_t>(positions.width));
        const int y = static_cast<int>(bestRoot / static_cast<std::size_t>(positions.width));
        quality.largestCopyOffsetX = positions.sourceX[bestRoot] - x;
        quality.largestCopyOffsetY = positions.sourceY[bestRoot] - y;
    }
    quality.largestCopyFraction =
        count > 0 ? static_cast<double>(quality.largestCopy) / static_cast<double>(count) : kNaN;
}

}  // namespace vpe::quilt::metrics
