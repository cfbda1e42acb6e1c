// SPDX-License-Identifier: MIT
// BilinearLightGrid: the light grid of Relight's "bilinear" RTI basis — R×R directions on an
// octahedral map of the upper hemisphere, looked up by bilinear interpolation exactly as
// OpenLIME's shader (ShaderRTI.js, BLN.lightWeights) does. docs/relight-export.md has the maths.
#pragma once

#include <array>

#include "vpe/capture/capture.h"

namespace vpe::relight_web {

// The four grid nodes (index x + y·R) a light blends and their weights (summing to 1).
struct LightGridWeights {
    std::array<int, 4> nodes{};
    std::array<double, 4> weights{};
};

class BilinearLightGrid {
public:
    // Relight accepts 2..20; vpe allows up to kMaxResolution, which OpenLIME reads the same way.
    static constexpr int kMinResolution = 2;
    static constexpr int kMaxResolution = 64;

    // `resolution` must lie in [kMinResolution, kMaxResolution] (std::invalid_argument).
    explicit BilinearLightGrid(int resolution);

    int resolution() const { return resolution_; }
    int nodeCount() const { return resolution_ * resolution_; }

    // The unit direction towards the light at node x + y·R (Relight's fromOcta: the square's
    // corners land on the horizon, z is clamped at 0 against rounding, then normalized).
    proto::Vec3d nodeDirection(int node) const;

    // The nodes and weights OpenLIME blends for the unit direction towards a light.
    LightGridWeights weights(const proto::Vec3d& towardsLight) const;

private:
    int resolution_;
};

}  // namespace vpe::relight_web
