// SPDX-License-Identifier: MIT
// The decoders' shared steps: the noise fit, the mixed pixels, the tally.
#include "decoding_steps.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "vpe/common/parallel_for.h"
#include "vpe/common/quantile.h"

namespace vpe::structured_light::detail {

NoiseModel fitNoiseModel(const std::vector<double>& level, const std::vector<double>& residual,
                         double quantum) {
    NoiseModel model;
    // Four images, two at each of two levels whose sum is x: var(r) = 4a + 2b·x (for
    // p + i − W − B, 2σ²(W) + 2σ²(B) = 4a + 2b·(W + B)). A line through the binned variances
    // (robust: MAD per bin).
    constexpr int kBins = 16;
    std::vector<std::vector<double>> bins(kBins);
    std::vector<std::vector<double>> levels(kBins);
    for (std::size_t k = 0; k < level.size(); ++k) {
        const int bin = std::clamp(static_cast<int>(level[k] / 2 * kBins), 0, kBins - 1);
        bins[static_cast<std::size_t>(bin)].push_back(residual[k]);
        levels[static_cast<std::size_t>(bin)].push_back(level[k]);
    }
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (int b = 0; b < kBins; ++b) {
        auto& values = bins[static_cast<std::size_t>(b)];
        if (values.size() < 64) {
            continue;
        }
        const double centre = common::quantile(values, 0.5);
        for (double& v : values) {
            v = std::abs(v - centre);
        }
        const double sigma = 1.4826 * common::quantile(values, 0.5);
        const double x = common::quantile(levels[static_cast<std::size_t>(b)], 0.5);
        const double y = sigma * sigma;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        n += 1;
    }
    double slope = 0, intercept = n > 0 ? sy / n : 0;
    if (n >= 2 && sxx * n - sx * sx > 1e-12) {
        slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        intercept = (sy - slope * sx) / n;
    }
    slope = std::max(slope, 0.0);
    // A capture without measurable noise still has its quantization's.
    model.constant = std::max(intercept / 4, quantum * quantum / 12);
    model.perSignal = slope / 2;
    return model;
}

void markMixedPixels(DecodedScan& scan, double maxBend, unsigned threads) {
    const std::size_t pixels = scan.status.size();
    // Mixed pixels across a jump: along a row or a column the decoded coordinates bend one way
    // at a pixel and the other way at its neighbour — a step, which a smooth surface, even seen
    // at a grazing angle (bends of one sign), does not make.
    const int w = scan.width, h = scan.height;
    const auto decodedAt = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < w && y < h &&
               scan.status[static_cast<std::size_t>(y) * w + x] == DecodeStatus::kDecoded;
    };
    // The bend of `map` at (x, y) along (dx, dy); NaN without both neighbours.
    const auto bend = [&](const std::vector<float>& map, int x, int y, int dx, int dy) {
        if (!decodedAt(x, y) || !decodedAt(x - dx, y - dy) || !decodedAt(x + dx, y + dy)) {
            return std::numeric_limits<double>::quiet_NaN();
        }
        const auto at = [&](int u, int v) {
            return double(map[static_cast<std::size_t>(v) * w + u]);
        };
        return at(x - dx, y - dy) + at(x + dx, y + dy) - 2 * at(x, y);
    };
    std::vector<std::uint8_t> edge(pixels, 0);
    common::parallelFor(
        static_cast<std::size_t>(h), 16, threads, [&](std::size_t begin, std::size_t end) {
            for (int y = static_cast<int>(begin); y < static_cast<int>(end); ++y) {
                for (int x = 0; x < w; ++x) {
                    if (!decodedAt(x, y)) {
                        continue;
                    }
                    bool step = false;
                    for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                        for (const std::vector<float>* map : {&scan.projectorX, &scan.projectorY}) {
                            const double here = bend(*map, x, y, dx, dy);
                            for (const int side : {-1, 1}) {
                                const double there =
                                    bend(*map, x + side * dx, y + side * dy, dx, dy);
                                step = step || (std::abs(here) > maxBend &&
                                                std::abs(there) > maxBend && here * there < 0);
                            }
                        }
                    }
                    edge[static_cast<std::size_t>(y) * w + x] = step ? 1 : 0;
                }
            }
        });
    for (std::size_t q = 0; q < pixels; ++q) {
        if (edge[q]) {
            scan.status[q] = DecodeStatus::kEdge;
            scan.projectorX[q] = scan.projectorY[q] = scan.precision[q] = kNaN;
        }
    }
}

void countStatuses(DecodedScan& scan, std::size_t lit) {
    scan.statusCounts.assign(kDecodeStatusCount, 0);
    for (const DecodeStatus status : scan.status) {
        ++scan.statusCounts[static_cast<std::size_t>(status)];
    }
    scan.decoded = scan.statusCounts[0];
    scan.lit = lit;
}

}  // namespace vpe::structured_light::detail
