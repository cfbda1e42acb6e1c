// SPDX-License-Identifier: MIT
// ScriptedLightPath: the virtual light until inputs arrive (issue 7). The light circles the
// screen object: centre c = the mesh's bounding-box centre, radius r = 2 × the box's half
// diagonal, on a cone 60° off the axis from c toward the viewer, so it always lights the side
// the visitor sees; one turn every `period` frames (default 120: 2 s at 60 Hz), starting on the
// side of the cone nearest the object's +x.
#pragma once

#include <array>
#include <span>

namespace vpe::firmware {

class ScriptedLightPath {
public:
    // positions: 3 floats per vertex (the bundle's mesh); viewer: the bundle's viewer position.
    ScriptedLightPath(std::span<const float> positions, const std::array<float, 3>& viewer,
                      int period = 120);
    std::array<float, 3> position(long frame) const;
    const std::array<float, 3>& centre() const { return centre_; }
    float radius() const { return radius_; }

private:
    std::array<float, 3> centre_{}, axis_{}, u_{}, w_{};
    float radius_ = 1;
    int period_;
};

}  // namespace vpe::firmware
