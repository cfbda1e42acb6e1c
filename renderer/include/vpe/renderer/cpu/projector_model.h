// SPDX-License-Identifier: MIT
// ProjectorModel: where the projector is, how its levels become light, and how much light.
#pragma once

#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/response_function.h"

namespace vpe::renderer {

// The irradiance a projector pixel at level v puts on a surface point X with unit normal n:
//   E = P · r(v) · cos θp / d²
// with d = |C − X| (metres), cos θp = n·(C − X)/d, C the projector's centre: P is the
// irradiance at 1 m, normal incidence, level 1 (in the units the light intensities use).
struct ProjectorModel {
    proto::PinholeCamera camera;  // usually with lens distortion
    proto::ResponseFunction response;
    double peakIrradiance = 1.0;  // P > 0
};

}  // namespace vpe::renderer
