// SPDX-License-Identifier: MIT
// LightSphere: the frame the virtual light moves in, as documented for OSC in proto/OSC.md.
// Centre: the screen mesh's bounding-box centre. Up: the object frame's +y (the bundle's
// convention). Azimuth 0 points from the centre toward the bundle's viewer (projected onto the
// horizontal plane), positive counter-clockwise seen from above (toward +x when the viewer is
// on +z). Elevation: above the horizontal plane. Distance: metres from the centre.
#pragma once

#include <array>
#include <span>

#include "vpe/firmware/input/spherical_position.h"

namespace vpe::firmware {

class LightSphere {
public:
    // positions: the bundle mesh's vertices, 3 floats each; viewer: the bundle's viewer.
    LightSphere(std::span<const float> positions, const std::array<float, 3>& viewer);

    std::array<double, 3> toPosition(const SphericalPosition& spherical) const;
    // The inverse; a position at the centre has distance 0 and angles 0.
    SphericalPosition fromPosition(const std::array<double, 3>& position) const;

    const std::array<double, 3>& centre() const { return centre_; }
    // Half the bounding box's diagonal: the scale of default distances.
    double objectRadius() const { return objectRadius_; }

private:
    std::array<double, 3> centre_{};
    std::array<double, 3> forward_{0, 0, 1};  // azimuth 0, horizontal
    std::array<double, 3> side_{1, 0, 0};     // azimuth +90°
    double objectRadius_ = 0.1;
};

}  // namespace vpe::firmware
