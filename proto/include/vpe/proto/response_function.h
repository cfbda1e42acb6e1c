// SPDX-License-Identifier: MIT
// ResponseFunction: the projector's relative output r(level) per channel — the fraction of
// the channel's full output at a drive level in [0, 1] — and its inverse for compensation. The
// math of the bundle's ResponseCurves (bundle_contents.h: the data), one implementation for
// the offline tools, the CPU reference and the device.
#pragma once

#include <array>
#include <vector>

#include "vpe/proto/bundle_contents.h"

namespace vpe::proto {

class ResponseFunction {
public:
    // Linear: r(level) = level.
    ResponseFunction() = default;

    // r(level) = level^γ per channel, γ > 0. Throws std::invalid_argument otherwise.
    static ResponseFunction gamma(double exponent);
    static ResponseFunction gamma(const std::array<double, 3>& exponents);
    // Piecewise linear through N ≥ 2 samples (levels[k], outputs[c][k]): levels strictly
    // increasing from exactly 0 to exactly 1 (a bundle's curve: levels[k] = k / (N − 1)),
    // outputs finite, ≥ 0, non-decreasing, last > first. Each channel is divided by its
    // output at level 1, so r(1) = 1; r(0) ≥ 0 is the black level. Throws
    // std::invalid_argument naming the problem.
    static ResponseFunction sampled(std::vector<double> levels,
                                    std::array<std::vector<double>, 3> outputs);
    // The same with levels of its own per channel (a bundle's channels may have different
    // sample counts).
    static ResponseFunction sampled(std::array<std::vector<double>, 3> levels,
                                    std::array<std::vector<double>, 3> outputs);

    bool isGamma() const { return levels_[0].empty(); }

    // r(level) of channel 0, 1, 2 (R, G, B); level is clamped to [0, 1], NaN reads as 0.
    double output(int channel, double level) const;
    // The inverse with clamping: the lowest level whose output reaches `fraction`. Fractions
    // at or below the black level give 0, at or above 1 give the lowest level reaching full
    // output (1 for a gamma); NaN gives 0.
    double level(int channel, double fraction) const;
    // r(0): 0 for a gamma.
    double blackLevel(int channel) const { return output(channel, 0.0); }

private:
    std::array<double, 3> exponents_{1, 1, 1};
    std::array<std::vector<double>, 3> levels_;   // empty for a gamma
    std::array<std::vector<double>, 3> outputs_;  // normalized, r(1) = 1
};

// The inverse response as the device looks it up (a texture, one filtered fetch per channel,
// instead of a search through the curve's samples): the level at u = √r on an even grid of
// `samples` values of u in [0, 1], linear in u between them. √ spreads the samples where a
// projector's inverse is steepest, near black (level ≈ r^(1/γ) ≈ u^0.9 is nearly straight in
// u): with 256 samples it is within 2e-4 of the exact inverse for curves like γ = 2.2–2.8.
class InverseResponseTable {
public:
    // samples ≥ 2; std::invalid_argument otherwise.
    InverseResponseTable(const ResponseFunction& response, int samples = 256);
    int samples() const { return samples_; }
    // The level for relative output r, clamped to [0, 1] (NaN reads as 0).
    double level(int channel, double relative) const;
    // Sample i of channel c: the level at u = i / (samples − 1), rounded to a half float.
    const std::vector<float>& levels(int channel) const {
        return levels_[static_cast<std::size_t>(channel)];
    }

private:
    int samples_ = 0;
    std::array<std::vector<float>, 3> levels_;
};

// The function a bundle's response curves describe: a gamma stays a gamma; sample i of a
// curve of N sits at level i / (N − 1). Throws std::invalid_argument, as gamma() and sampled()
// do, for values they refuse (a bundle's reader has refused them already: checkSettings).
ResponseFunction responseFunctionOf(const ResponseCurves& curves);

}  // namespace vpe::proto
