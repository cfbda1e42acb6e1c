// SPDX-License-Identifier: MIT
// ResponseInput: the projector response as the offline tools take it (`vpe bake --response`):
// how a projector's drive level (0..1, what the frame buffer holds) turns into light, per
// channel, as a fraction of the channel's full output. Compensation needs the inverse: the
// level that makes a wanted fraction. A gamma per channel, or a measured curve read from CSV
// with levels of its own. This class reads and checks them with offline-grade messages and
// keeps the gammas for the bundle (bake/bake_inputs.h); the curve and its inverse are
// proto::ResponseFunction's, the device's own.
#pragma once

#include <array>
#include <filesystem>
#include <string_view>
#include <vector>

#include "vpe/proto/response_function.h"

namespace vpe::scene {

class ResponseInput {
public:
    // output = level^γ per channel; γ > 0.
    static ResponseInput gamma(double exponent);
    static ResponseInput gamma(const std::array<double, 3>& exponents);
    // Piecewise linear through (levels[k], outputs[c][k]): levels strictly increasing from
    // 0 to 1, outputs finite, ≥ 0, non-decreasing and rising overall; each channel is
    // divided by its output at level 1 (outputs may be in any unit, e.g. cd/m²). Throws
    // InputError naming `source` otherwise.
    static ResponseInput sampled(std::vector<double> levels,
                                 std::array<std::vector<double>, 3> outputs,
                                 std::string_view source = "response");

    bool isGamma() const { return curve_.isGamma(); }
    const std::array<double, 3>& exponents() const { return exponents_; }

    // Fraction of full output at a drive level (clamped to [0, 1]) of channel 0, 1, 2 (r g b).
    double output(int channel, double level) const;
    // The inverse: the lowest level whose output reaches `fraction`. Fractions below the
    // black level give 0, above full output 1; NaN gives 0.
    double level(int channel, double fraction) const;

    std::array<double, 3> output(const std::array<double, 3>& levels) const;
    std::array<double, 3> level(const std::array<double, 3>& fractions) const;

private:
    ResponseInput() = default;

    std::array<double, 3> exponents_{1, 1, 1};
    proto::ResponseFunction curve_;  // the math, shared with the device
};

// A measured curve: one "level,r,g,b" row per sample, levels from 0 to 1 increasing, outputs
// monotone non-decreasing; blank lines and # comments are skipped, and the first row may be
// a header (level,r,g,b). Throws InputError "PATH:LINE: problem" for bad numbers, wrong
// field counts, non-monotone rows, and "PATH: problem" for too few samples (at least 2,
// covering levels 0 and 1) or a flat channel.
ResponseInput readProjectorResponseCsv(const std::filesystem::path& path);

// The --response argument: "2.2" (one gamma), "2.2,2.2,2.4" (per channel) or the path of a
// CSV file as above.
ResponseInput parseProjectorResponse(std::string_view argument);

}  // namespace vpe::scene
