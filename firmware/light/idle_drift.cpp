// SPDX-License-Identifier: MIT
#include "vpe/firmware/light/idle_drift.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vpe::firmware {

SphericalPosition IdleDrift::path(double seconds, double distanceM) const {
    const double phase = 2.0 * std::numbers::pi * seconds / config_.periodSeconds;
    const auto between = [](const std::pair<double, double>& range, double wave) {
        return 0.5 * (range.first + range.second) + 0.5 * (range.second - range.first) * wave;
    };
    // Azimuth once, elevation twice per period: a figure of eight that starts at the ranges'
    // centres, heading right and up.
    return {between(config_.azimuthDeg, std::sin(phase)),
            between(config_.elevationDeg, std::sin(2.0 * phase)), distanceM};
}

double IdleDrift::phaseAt(std::int64_t nowNs) const {
    // In integer nanoseconds: a wall clock's 1.7e18 ns as a double would lose the phase's
    // sub-microsecond steps.
    const auto periodNs = std::max<std::int64_t>(std::llround(config_.periodSeconds * 1e9), 1);
    const std::int64_t within = ((nowNs % periodNs) + periodNs) % periodNs;
    return static_cast<double>(within) * 1e-9;
}

SphericalPosition IdleDrift::position(const SphericalPosition& from, double sinceStart,
                                      double pathSeconds) const {
    const SphericalPosition onPath = path(pathSeconds, from.distanceM);
    if (config_.handoverSeconds <= 0 || sinceStart >= config_.handoverSeconds) {
        return onPath;
    }
    const double t = std::clamp(sinceStart / config_.handoverSeconds, 0.0, 1.0);
    const double w = t * t * (3.0 - 2.0 * t);
    // The shortest way round in azimuth, so a light at +170° does not sweep through 0°.
    double dAz = std::remainder(onPath.azimuthDeg - from.azimuthDeg, 360.0);
    return {from.azimuthDeg + w * dAz,
            from.elevationDeg + w * (onPath.elevationDeg - from.elevationDeg), from.distanceM};
}

}  // namespace vpe::firmware
