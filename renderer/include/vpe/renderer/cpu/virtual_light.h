// SPDX-License-Identifier: MIT
// VirtualLight: the light the visitors move, which lights the virtual material (not the room).
#pragma once

#include <array>

#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer {

// A point light. The irradiance it gives a surface point X, measured perpendicular to the
// light (proto/MODEL.md: f already holds the cos θd of the Lambert term), is its intensity —
// no distance falloff, like the capture's unit lights — or, with inverseSquare,
// intensity · (referenceDistance / |position − X|)².
struct VirtualLight {
    Vec3d position{0, 0, 1};  // object frame, metres
    std::array<double, 3> intensity{1, 1, 1};
    bool inverseSquare = false;
    double referenceDistance = 1.0;  // metres, > 0

    std::array<double, 3> irradianceAt(const Vec3d& point) const;
};

}  // namespace vpe::renderer
