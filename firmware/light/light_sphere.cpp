// SPDX-License-Identifier: MIT
#include "vpe/firmware/light/light_sphere.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vpe::firmware {

namespace {

using Vec = std::array<double, 3>;

double dot(const Vec& a, const Vec& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

constexpr double kDegree = std::numbers::pi / 180.0;

}  // namespace

LightSphere::LightSphere(std::span<const float> positions, const std::array<float, 3>& viewer) {
    Vec low{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
            std::numeric_limits<double>::max()};
    Vec high{-low[0], -low[1], -low[2]};
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        for (std::size_t a = 0; a < 3; ++a) {
            low[a] = std::min(low[a], static_cast<double>(positions[i + a]));
            high[a] = std::max(high[a], static_cast<double>(positions[i + a]));
        }
    }
    if (positions.size() < 3) {
        low = high = Vec{0, 0, 0};
    }
    Vec half{};
    for (std::size_t a = 0; a < 3; ++a) {
        half[a] = 0.5 * (high[a] - low[a]);
        centre_[a] = low[a] + half[a];
    }
    objectRadius_ = std::max(std::sqrt(dot(half, half)), 1e-3);
    // Azimuth 0: toward the viewer, flattened onto the horizontal plane (y up). A viewer
    // straight above the object leaves no horizontal direction: +z then.
    Vec toViewer{static_cast<double>(viewer[0]) - centre_[0], 0.0,
                 static_cast<double>(viewer[2]) - centre_[2]};
    const double length = std::sqrt(dot(toViewer, toViewer));
    forward_ = length > 1e-9 ? Vec{toViewer[0] / length, 0.0, toViewer[2] / length} : Vec{0, 0, 1};
    // up × forward: +x for forward +z, i.e. counter-clockwise seen from above.
    side_ = {forward_[2], 0.0, -forward_[0]};
}

std::array<double, 3> LightSphere::toPosition(const SphericalPosition& s) const {
    const double az = s.azimuthDeg * kDegree, el = s.elevationDeg * kDegree;
    const double horizontal = std::cos(el) * s.distanceM;
    const double a = horizontal * std::cos(az), b = horizontal * std::sin(az);
    return {centre_[0] + a * forward_[0] + b * side_[0], centre_[1] + s.distanceM * std::sin(el),
            centre_[2] + a * forward_[2] + b * side_[2]};
}

SphericalPosition LightSphere::fromPosition(const std::array<double, 3>& position) const {
    const Vec d{position[0] - centre_[0], position[1] - centre_[1], position[2] - centre_[2]};
    SphericalPosition s;
    s.distanceM = std::sqrt(dot(d, d));
    if (s.distanceM < 1e-12) {
        return {0.0, 0.0, 0.0};
    }
    s.elevationDeg = std::asin(std::clamp(d[1] / s.distanceM, -1.0, 1.0)) / kDegree;
    s.azimuthDeg = std::atan2(dot(d, side_), dot(d, forward_)) / kDegree;
    return s;
}

}  // namespace vpe::firmware
