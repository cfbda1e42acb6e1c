// SPDX-License-Identifier: MIT
// The octahedral light grid of Relight's bilinear basis.
#include "vpe/relight_web/bilinear_light_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vpe::relight_web {

BilinearLightGrid::BilinearLightGrid(int resolution) : resolution_(resolution) {
    if (resolution < kMinResolution || resolution > kMaxResolution) {
        throw std::invalid_argument("light grid resolution " + std::to_string(resolution) +
                                    " is outside " + std::to_string(kMinResolution) + ".." +
                                    std::to_string(kMaxResolution));
    }
}

proto::Vec3d BilinearLightGrid::nodeDirection(int node) const {
    const int x = node % resolution_;
    const int y = node / resolution_;
    // Node coordinates in the rotated square [−1, 1]², then back to the octahedral diamond.
    const double u = 2.0 * x / (resolution_ - 1) - 1.0;
    const double v = 2.0 * y / (resolution_ - 1) - 1.0;
    const double dx = (u - v) / 2.0;
    const double dy = (u + v) / 2.0;
    const double dz = std::max(0.0, 1.0 - std::abs(dx) - std::abs(dy));
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    return proto::Vec3d{dx / length, dy / length, dz / length};
}

LightGridWeights BilinearLightGrid::weights(const proto::Vec3d& towardsLight) const {
    const double s = std::abs(towardsLight.x) + std::abs(towardsLight.y) + std::abs(towardsLight.z);
    // A zero vector has no direction; OpenLIME would divide by zero, vpe looks straight down.
    const double u = s > 0 ? (towardsLight.x + towardsLight.y) / s : 0.0;
    const double v = s > 0 ? (towardsLight.y - towardsLight.x) / s : 0.0;
    const double gx = (u + 1.0) / 2.0 * (resolution_ - 1.0);
    const double gy = (v + 1.0) / 2.0 * (resolution_ - 1.0);
    const int sx = std::clamp(static_cast<int>(std::floor(gx)), 0, resolution_ - 2);
    const int sy = std::clamp(static_cast<int>(std::floor(gy)), 0, resolution_ - 2);
    const double fx = gx - sx;
    const double fy = gy - sy;
    LightGridWeights result;
    result.nodes = {sx + sy * resolution_, sx + 1 + sy * resolution_, sx + (sy + 1) * resolution_,
                    sx + 1 + (sy + 1) * resolution_};
    result.weights = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    return result;
}

}  // namespace vpe::relight_web
