// SPDX-License-Identifier: MIT
// Seam step against interior neighbour steps.
#include "texture/seam_statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vpe::texture {

namespace {

double quantile(std::vector<double> values, double share) {
    std::sort(values.begin(), values.end());
    const auto at =
        static_cast<std::size_t>(std::lround(share * static_cast<double>(values.size() - 1)));
    return values[at];
}

}  // namespace

SeamStatistics measureSeam(std::span<const float> values, int width, int height, int channels,
                           std::span<const unsigned char> valid) {
    if (width < 3 || height < 1 || channels < 1 ||
        values.size() != static_cast<std::size_t>(width) * height * channels ||
        (!valid.empty() && valid.size() != static_cast<std::size_t>(width) * height)) {
        throw std::invalid_argument("measureSeam: sizes do not match");
    }
    const auto texel = [&](int x, int y) {
        return values.data() + (static_cast<std::size_t>(y) * width + x) * channels;
    };
    const auto ok = [&](int x, int y) {
        return valid.empty() || valid[static_cast<std::size_t>(y) * width + x] != 0;
    };
    // Mean step between columns a and b over the rows where both are valid.
    const auto step = [&](int a, int b) {
        double sum = 0;
        int rows = 0;
        for (int y = 0; y < height; ++y) {
            if (!ok(a, y) || !ok(b, y)) {
                continue;
            }
            const float* p = texel(a, y);
            const float* q = texel(b, y);
            double d2 = 0;
            for (int c = 0; c < channels; ++c) {
                const double d = static_cast<double>(q[c]) - static_cast<double>(p[c]);
                d2 += d * d;
            }
            sum += std::sqrt(d2);
            ++rows;
        }
        return rows > 0 ? sum / rows : 0.0;
    };
    SeamStatistics s;
    s.columnSteps.resize(static_cast<std::size_t>(width - 1));
    double total = 0;
    for (int x = 0; x + 1 < width; ++x) {
        s.columnSteps[static_cast<std::size_t>(x)] = step(x, x + 1);
        total += s.columnSteps[static_cast<std::size_t>(x)];
    }
    s.seam = step(width - 1, 0);
    s.interiorMean = total / (width - 1);
    s.interiorMedian = quantile(s.columnSteps, 0.5);
    s.interiorP95 = quantile(s.columnSteps, 0.95);
    s.interiorMax = *std::max_element(s.columnSteps.begin(), s.columnSteps.end());
    const auto below = std::count_if(s.columnSteps.begin(), s.columnSteps.end(),
                                     [&](double v) { return v < s.seam; });
    s.seamRank = static_cast<double>(below) / static_cast<double>(s.columnSteps.size());
    return s;
}

}  // namespace vpe::texture
