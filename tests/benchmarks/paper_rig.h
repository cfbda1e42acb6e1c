// SPDX-License-Identifier: MIT
// The paper's light rig as directions: 6 heights × 55 positions 3° apart in front of the
// object (330 lights), the capture the speed and memory goals are stated for.
#pragma once

#include <cmath>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::benchmarks {

inline std::vector<proto::Vec3d> paperRigLights() {
    std::vector<proto::Vec3d> lights;
    for (int h = 0; h < 6; ++h) {
        const double elevation = (-20.0 + 12.0 * h) * M_PI / 180.0;
        for (int a = 0; a < 55; ++a) {
            const double azimuth = (-81.0 + 3.0 * a) * M_PI / 180.0;
            lights.push_back({std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                              std::cos(azimuth) * std::cos(elevation)});
        }
    }
    return lights;
}

}  // namespace vpe::benchmarks
