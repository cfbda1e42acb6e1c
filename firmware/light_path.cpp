// SPDX-License-Identifier: MIT
// ScriptedLightPath: a light circling the object on a cone around the viewer's direction.
#include "vpe/firmware/light_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vpe::firmware {

namespace {

using Vec = std::array<float, 3>;

Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

float norm(const Vec& a) {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

Vec normalized(const Vec& a, const Vec& fallback) {
    const float n = norm(a);
    return n > 1e-12f ? Vec{a[0] / n, a[1] / n, a[2] / n} : fallback;
}

}  // namespace

ScriptedLightPath::ScriptedLightPath(std::span<const float> positions, const Vec& viewer,
                                     int period)
    : period_(std::max(period, 1)) {
    Vec low{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
            std::numeric_limits<float>::max()};
    Vec high{-low[0], -low[1], -low[2]};
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        for (std::size_t a = 0; a < 3; ++a) {
            low[a] = std::min(low[a], positions[i + a]);
            high[a] = std::max(high[a], positions[i + a]);
        }
    }
    if (positions.size() < 3) {
        low = high = Vec{0, 0, 0};
    }
    const Vec half{0.5f * (high[0] - low[0]), 0.5f * (high[1] - low[1]), 0.5f * (high[2] - low[2])};
    centre_ = {low[0] + half[0], low[1] + half[1], low[2] + half[2]};
    radius_ = std::max(2.0f * norm(half), 1e-3f);
    axis_ = normalized({viewer[0] - centre_[0], viewer[1] - centre_[1], viewer[2] - centre_[2]},
                       Vec{0, 0, 1});
    // u: the object's +x made perpendicular to the axis (or +y when x is the axis).
    const Vec x = std::abs(axis_[0]) < 0.9f ? Vec{1, 0, 0} : Vec{0, 1, 0};
    w_ = normalized(cross(axis_, x), Vec{0, 1, 0});
    u_ = cross(w_, axis_);
}

Vec ScriptedLightPath::position(long frame) const {
    const double turn = static_cast<double>(frame % period_) / period_;
    const float phi = static_cast<float>(2.0 * std::numbers::pi * turn);
    constexpr float kOffAxis = std::numbers::pi_v<float> / 3.0f;  // 60°
    const float side = radius_ * std::sin(kOffAxis), along = radius_ * std::cos(kOffAxis);
    const float cu = side * std::cos(phi), cw = side * std::sin(phi);
    Vec p{};
    for (std::size_t a = 0; a < 3; ++a) {
        p[a] = centre_[a] + along * axis_[a] + cu * u_[a] + cw * w_[a];
    }
    return p;
}

}  // namespace vpe::firmware
