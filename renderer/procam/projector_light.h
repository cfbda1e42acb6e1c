// SPDX-License-Identifier: MIT
// ProjectorLight: the light a simulated projector sends through each point of its image for one
// frame — the drive levels through the response and the black level, spread by the defocus.
#pragma once

#include <array>
#include <vector>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::renderer::procam {

class ProjectorLight {
public:
    // levels: the projector's size, drive levels in [0, 1]. Throws std::invalid_argument for
    // another size.
    ProjectorLight(const SimulatedProjector& projector, const RgbImage& levels);

    // Relative output per channel at a projector image point (pixel centres at integers),
    // bilinear between pixel centres, clamped to the edge: a pixel's light is the Gaussian
    // defocus of its value convolved with the one-pixel tent of the interpolation.
    std::array<float, 3> at(float x, float y) const;

private:
    int width_ = 0, height_ = 0;
    std::vector<float> output_;  // width·height·3
};

}  // namespace vpe::renderer::procam
