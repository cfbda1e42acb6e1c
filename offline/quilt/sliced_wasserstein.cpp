// SPDX-License-Identifier: MIT
// Sliced 2-Wasserstein distance between sets of coefficient vectors: exact 1-D distances on
// seeded random directions.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "vpe/common/parallel_for.h"
#include "vpe/common/random_bits.h"

#include "quality_metrics.h"

namespace vpe::quilt {

namespace {

using metrics::evenSubset;
using metrics::kNaN;

// W₂² between the empirical distributions of two sorted samples, exactly: the quantile
// functions are step functions with breaks at i/n and j/m, merged on the denominator n·m.
double wassersteinSquared1d(const std::vector<double>& a, const std::vector<double>& b) {
    const std::uint64_t n = a.size(), m = b.size();
    std::uint64_t i = 0, j = 0, t = 0;
    double sum = 0;
    while (i < n && j < m) {
        const std::uint64_t endA = (i + 1) * m, endB = (j + 1) * n;
        const std::uint64_t next = std::min(endA, endB);
        const double d = a[i] - b[j];
        sum += static_cast<double>(next - t) * d * d;
        t = next;
        if (endA == next) {
            ++i;
        }
        if (endB == next) {
            ++j;
        }
    }
    return sum / (static_cast<double>(n) * static_cast<double>(m));
}

// A Gaussian vector from the counter-based stream, normalized: a uniform random direction.
std::vector<double> randomDirection(std::uint64_t seed, int direction, int dims) {
    std::vector<double> v(static_cast<std::size_t>(dims));
    double norm = 0;
    for (int d = 0; d < dims; ++d) {
        const std::uint64_t key =
            common::mixBits(seed ^ common::mixBits(static_cast<std::uint64_t>(direction) * 4099 +
                                                   static_cast<std::uint64_t>(d)));
        const double u1 = 1.0 - common::uniformFromBits(key);  // (0, 1]: log is finite
        const double u2 = common::uniformFromBits(common::mixBits(key));
        v[static_cast<std::size_t>(d)] =
            std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
        norm += v[static_cast<std::size_t>(d)] * v[static_cast<std::size_t>(d)];
    }
    norm = std::sqrt(norm);
    for (double& x : v) {
        x /= norm;
    }
    return v;
}

}  // namespace

double slicedWasserstein(const float* a, std::size_t countA, const float* b, std::size_t countB,
                         int dims, const SlicedWassersteinOptions& options) {
    if (countA == 0 || countB == 0 || dims <= 0 || options.directions <= 0) {
        return kNaN;
    }
    const std::vector<std::size_t> subsetA = evenSubset(countA, options.maxSamples);
    const std::vector<std::size_t> subsetB = evenSubset(countB, options.maxSamples);
    std::vector<double> squared(static_cast<std::size_t>(options.directions));
    common::parallelFor(
        squared.size(), 1, options.threads, [&](std::size_t begin, std::size_t end) {
            std::vector<double> projectedA(subsetA.size()), projectedB(subsetB.size());
            for (std::size_t t = begin; t < end; ++t) {
                const std::vector<double> direction =
                    randomDirection(options.seed, static_cast<int>(t), dims);
                auto project = [&](const float* set, const std::vector<std::size_t>& subset,
                                   std::vector<double>& projected) {
                    for (std::size_t i = 0; i < subset.size(); ++i) {
                        const float* v = set + subset[i] * dims;
                        double sum = 0;
                        for (int d = 0; d < dims; ++d) {
                            sum +=
                                direction[static_cast<std::size_t>(d)] * static_cast<double>(v[d]);
                        }
                        projected[i] = sum;
                    }
                    std::sort(projected.begin(), projected.end());
                };
                project(a, subsetA, projectedA);
                project(b, subsetB, projectedB);
                squared[t] = wassersteinSquared1d(projectedA, projectedB);
            }
        });
    return std::sqrt(std::accumulate(squared.begin(), squared.end(), 0.0) /
                     static_cast<double>(squared.size()));
}

}  // namespace vpe::quilt
