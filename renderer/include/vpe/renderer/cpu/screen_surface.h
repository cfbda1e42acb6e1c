// SPDX-License-Identifier: MIT
// ScreenSurface: the white plaster object, a Lambertian reflector, and the room's other light.
#pragma once

#include <array>

namespace vpe::renderer {

// The plaster sends radiance ρ/π · (E_projector + E_ambient) in every direction, per channel.
struct ScreenSurface {
    std::array<double, 3> albedo{0.85, 0.85, 0.85};  // ρ, linear RGB, in (0, 1]
    // Irradiance the room adds everywhere on the object (same units as the projector's peak
    // irradiance), ≥ 0. Not shadowed, not direction dependent.
    std::array<double, 3> ambientIrradiance{0, 0, 0};
};

}  // namespace vpe::renderer
