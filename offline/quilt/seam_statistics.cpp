// SPDX-License-Identifier: MIT
// Seam step against interior neighbour steps.
#include "vpe/quilt/seam_statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "vpe/common/parallel_for.h"
#include "vpe/common/quantile.h"

namespace vpe::quilt {

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
    // Mean step between columns a and b over the rows where both are valid, for the column
    // pairs x → x + 1 of [begin, end) (x = width − 1 pairs with column 0: the seam). Rows in
    // the outer loop: a column-at-a-time walk strode a whole row per texel and took a
    // second per 2048² × 66 map; each column's sum still runs over y in order, so the
    // figures are the same to the bit.
    const auto steps = [&](std::size_t begin, std::size_t end, double* out) {
        std::vector<double> sum(end - begin, 0.0);
        std::vector<int> rows(end - begin, 0);
        for (int y = 0; y < height; ++y) {
            for (std::size_t x = begin; x < end; ++x) {
                const int a = static_cast<int>(x);
                const int b = a + 1 < width ? a + 1 : 0;
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
                sum[x - begin] += std::sqrt(d2);
                ++rows[x - begin];
            }
        }
        for (std::size_t i = 0; i < sum.size(); ++i) {
            out[i] = rows[i] > 0 ? sum[i] / rows[i] : 0.0;
        }
    };
    std::vector<double> all(static_cast<std::size_t>(width));
    common::parallelFor(
        all.size(), 64, common::resolveThreadCount(0),
        [&](std::size_t begin, std::size_t end) { steps(begin, end, all.data() + begin); });
    SeamStatistics s;
    s.columnSteps.assign(all.begin(), all.end() - 1);
    double total = 0;
    for (const double v : s.columnSteps) {
        total += v;
    }
    s.seam = all.back();
    s.interiorMean = total / (width - 1);
    s.interiorMedian = common::quantile(s.columnSteps, 0.5);
    s.interiorP95 = common::quantile(s.columnSteps, 0.95);
    s.interiorMax = *std::max_element(s.columnSteps.begin(), s.columnSteps.end());
    const auto below = std::count_if(s.columnSteps.begin(), s.columnSteps.end(),
                                     [&](double v) { return v < s.seam; });
    s.seamRank = static_cast<double>(below) / static_cast<double>(s.columnSteps.size());
    return s;
}

nlohmann::json seamJson(const SeamStatistics& s) {
    return {{"step", s.seam},
            {"interior_mean", s.interiorMean},
            {"interior_median", s.interiorMedian},
            {"interior_p95", s.interiorP95},
            {"interior_max", s.interiorMax},
            {"rank", s.seamRank},
            {"ratio", s.ratio()}};
}

}  // namespace vpe::quilt
