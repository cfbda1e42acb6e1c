// SPDX-License-Identifier: MIT
// SphericalPosition: where the light stands on its sphere about the object (the frame of
// light/light_sphere.h and proto/OSC.md), the coordinates the inputs, the rig and the bus all
// speak in.
#pragma once

namespace vpe::firmware {

// Degrees, metres.
struct SphericalPosition {
    double azimuthDeg = 0, elevationDeg = 0, distanceM = 1;
};

}  // namespace vpe::firmware
