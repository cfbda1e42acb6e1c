// SPDX-License-Identifier: MIT
// Seam smoothness of a quilt: mean squared differences across block seams against interiors.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "quality_metrics.h"

namespace vpe::quilt::metrics {

namespace {

double squaredDifference(const float* a, const float* b, int dims) {
    double sum = 0;
    for (int d = 0; d < dims; ++d) {
        const double diff = static_cast<double>(a[d]) - static_cast<double>(b[d]);
        sum += diff * diff;
    }
    return sum / dims;
}

}  // namespace

void measureSeams(const model::CoefficientImage& source, const std::vector<std::uint8_t>& mask,
                  const model::CoefficientImage& output, const PositionMap& positions,
                  RegionQuality& quality) {
    double seamSum = 0, interiorSum = 0;
    for (int y = 0; y < output.height; ++y) {
        for (int x = 0; x < output.width; ++x) {
            const std::size_t p = positions.pixel(x, y);
            if (!positions.known(p)) {
                continue;
            }
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (x + dx >= output.width || y + dy >= output.height) {
                    continue;
                }
                const std::size_t q = positions.pixel(x + dx, y + dy);
                if (!positions.known(q)) {
                    continue;
                }
                // Same offset: the sources are neighbours in the same direction.
                const bool interior = positions.sourceX[q] - positions.sourceX[p] == dx &&
                                      positions.sourceY[q] - positions.sourceY[p] == dy;
                const double difference =
                    squaredDifference(output.at(p), output.at(q), output.dims);
                if (interior) {
                    interiorSum += difference;
                    ++quality.interiorPairs;
                } else {
                    seamSum += difference;
                    ++quality.seamPairs;
                }
            }
        }
    }
    if (quality.interiorPairs == 0) {
        // No block interior to compare with (a pixel shuffle): every output interior pair
        // would be a neighbour pair of the source region, so take those.
        quality.interiorFromSource = true;
        for (int y = 0; y < source.height; ++y) {
            for (int x = 0; x < source.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * source.width + x;
                if (!mask[p]) {
                    continue;
                }
                if (x + 1 < source.width && mask[p + 1]) {
                    interiorSum += squaredDifference(source.at(p), source.at(p + 1), source.dims);
                    ++quality.interiorPairs;
                }
                if (y + 1 < source.height && mask[p + source.width]) {
                    interiorSum +=
                        squaredDifference(source.at(p), source.at(p + source.width), source.dims);
                    ++quality.interiorPairs;
                }
            }
        }
    }
    quality.seamMsd =
        quality.seamPairs > 0 ? seamSum / static_cast<double>(quality.seamPairs) : kNaN;
    quality.interiorMsd =
        quality.interiorPairs > 0 ? interiorSum / static_cast<double>(quality.interiorPairs) : kNaN;
    quality.seamRatio = quality.interiorMsd > 0 ? quality.seamMsd / quality.interiorMsd : kNaN;
}

}  // namespace vpe::quilt::metrics
