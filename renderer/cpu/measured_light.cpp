// SPDX-License-Identifier: MIT
// The compensation from measured light (see the header).
#include "vpe/renderer/cpu/measured_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vpe::renderer {

std::array<double, 9> inverse3x3(const std::array<double, 9>& m) {
    const double a = m[4] * m[8] - m[5] * m[7], b = m[5] * m[6] - m[3] * m[8],
                 c = m[3] * m[7] - m[4] * m[6];
    const double determinant = m[0] * a + m[1] * b + m[2] * c;
    if (!(std::abs(determinant) > 1e-12) || !std::isfinite(determinant)) {
        throw std::invalid_argument("the crosstalk matrix is singular");
    }
    const double s = 1.0 / determinant;
    return {a * s, (m[2] * m[7] - m[1] * m[8]) * s, (m[1] * m[5] - m[2] * m[4]) * s,
            b * s, (m[0] * m[8] - m[2] * m[6]) * s, (m[2] * m[3] - m[0] * m[5]) * s,
            c * s, (m[1] * m[6] - m[0] * m[7]) * s, (m[0] * m[4] - m[1] * m[3]) * s};
}

bool rollOffHighlight(std::array<double, 3>& outputs) {
    const double t = std::max({outputs[0], outputs[1], outputs[2]});
    if (!(t > kHighlightKnee)) {
        return false;
    }
    const double span = 1 - kHighlightKnee;
    const double rolled =
        std::isinf(t) ? 1.0 : kHighlightKnee + span * std::tanh((t - kHighlightKnee) / span);
    for (double& w : outputs) {
        w = std::isinf(t) ? (std::isinf(w) ? rolled : 0.0) : w * (rolled / t);
    }
    return true;
}

CompensatedPixel compensateMeasuredPixel(const float* irradiance, const float* floor,
                                         const std::array<double, 9>& mixingInverse,
                                         const proto::InverseResponseTable& inverseResponse,
                                         const std::array<double, 3>& target, double gain) {
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    std::array<double, 3> mixed{}, perGain{}, fromFloor{};
    for (std::size_t k = 0; k < 3; ++k) {
        const double f = static_cast<double>(irradiance[k]);
        const double wanted = target[k] - static_cast<double>(floor[k]);
        if (f > 0) {
            mixed[k] = wanted / f;
            perGain[k] = target[k] / f;
            fromFloor[k] = static_cast<double>(floor[k]) / f;
        } else {
            mixed[k] = wanted > 0 ? kInfinity : (wanted < 0 ? -kInfinity : 0.0);
            perGain[k] = target[k] > 0 ? kInfinity : 0.0;
        }
    }
    std::array<double, 3> outputs{};
    CompensatedPixel pixel;
    pixel.gainLimit = kInfinity;
    // No light measured in some channel: nothing to unmix; each primary full where its channel
    // wants light, none elsewhere, as compensatePixel does where the projector cannot reach.
    const bool unmeasured = !(irradiance[0] > 0 && irradiance[1] > 0 && irradiance[2] > 0);
    if (unmeasured) {
        for (std::size_t c = 0; c < 3; ++c) {
            const bool wants = target[c] - static_cast<double>(floor[c]) > 0;
            pixel.level[c] = inverseResponse.level(static_cast<int>(c), wants ? 1.0 : 0.0);
            pixel.clippedHigh = pixel.clippedHigh || wants;
            if (target[c] > 0) {
                pixel.gainLimit = 0;
            }
        }
        return pixel;
    }
    for (std::size_t c = 0; c < 3 && !unmeasured; ++c) {
        double w = 0, a = 0, b = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const double x = mixingInverse[3 * c + k];
            if (x != 0) {
                w += x * mixed[k];
                a += x * perGain[k];
                b += x * fromFloor[k];
            }
        }
        outputs[c] = std::isnan(w) ? 0.0 : w;
        // w_c(g) = (g / gain) · a − b ≤ κ  ⇔  g ≤ gain · (κ + b) / a, for a > 0.
        if (a > 0) {
            pixel.gainLimit = std::min(pixel.gainLimit, gain * (kHighlightKnee + b) / a);
        }
    }
    pixel.clippedHigh = rollOffHighlight(outputs);
    for (std::size_t c = 0; c < 3; ++c) {
        if (outputs[c] < 0) {
            outputs[c] = 0;
            pixel.clippedLow = true;
        }
        pixel.level[c] = inverseResponse.level(static_cast<int>(c), outputs[c]);
    }
    return pixel;
}

}  // namespace vpe::renderer
