// SPDX-License-Identifier: MIT
#include "vpe/renderer/cpu/loop_closure.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace vpe::renderer {

namespace {

// The projector pixels bilinear sampling at p blends: all must cover the object, unclipped,
// for the simulated light there to be the compensated one.
bool cleanNeighbourhood(const ProjectorFrame& frame, float px, float py) {
    const int x0 = static_cast<int>(std::floor(px)), y0 = static_cast<int>(std::floor(py));
    for (int y = y0; y <= y0 + 1; ++y) {
        for (int x = x0; x <= x0 + 1; ++x) {
            if (x < 0 || y < 0 || x >= frame.coverage.width || y >= frame.coverage.height ||
                !frame.coverage.at(x, y) || frame.clipped.at(x, y)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

LoopClosure compareVisitorViews(const ProjectorFrame& frame, const SimulatedView& simulated,
                                const DirectView& direct) {
    LoopClosure result;
    const std::size_t pixels = direct.coverage.values.size();
    float brightest = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (direct.coverage.values[p]) {
            for (int c = 0; c < 3; ++c) {
                brightest = std::max(brightest,
                                     direct.radiance.values[p * 3 + static_cast<std::size_t>(c)]);
            }
        }
    }
    std::vector<double> errors;
    double squared = 0;
    std::size_t squaredCount = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        if (!direct.coverage.values[p]) {
            continue;
        }
        ++result.seenPixels;
        if (!simulated.lit.values[p]) {
            ++result.shadowedPixels;
            continue;
        }
        if (!cleanNeighbourhood(frame, simulated.projectorPixel[2 * p],
                                simulated.projectorPixel[2 * p + 1])) {
            continue;
        }
        ++result.comparedPixels;
        for (int c = 0; c < 3; ++c) {
            const std::size_t i = p * 3 + static_cast<std::size_t>(c);
            const double truth = static_cast<double>(direct.radiance.values[i]);
            const double difference = static_cast<double>(simulated.radiance.values[i]) - truth;
            squared += difference * difference;
            ++squaredCount;
            if (truth < 0.05 * static_cast<double>(brightest)) {
                continue;
            }
            errors.push_back(std::fabs(static_cast<double>(simulated.radiance.values[i]) - truth) /
                             truth);
        }
    }
    if (squaredCount > 0 && brightest > 0) {
        const double mse = squared / static_cast<double>(squaredCount);
        const double peak = static_cast<double>(brightest);
        result.psnr = mse > 0 ? 10.0 * std::log10(peak * peak / mse) : 200.0;
    }
    if (!errors.empty()) {
        double sum = 0;
        for (double e : errors) {
            sum += e;
        }
        result.meanRelativeError = sum / static_cast<double>(errors.size());
        std::sort(errors.begin(), errors.end());
        result.p99RelativeError =
            errors[static_cast<std::size_t>(0.99 * static_cast<double>(errors.size() - 1))];
        result.maxRelativeError = errors.back();
    }
    return result;
}

}  // namespace vpe::renderer
