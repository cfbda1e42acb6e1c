// SPDX-License-Identifier: MIT
// ProjectorLight: the light a simulated projector sends through each point of its image for one
// frame — the drive levels through the response (and a DLP's bit-planes over the camera's
// exposure window) and the black level, spread by the defocus.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/procam/procam_scene.h"

namespace vpe::renderer::procam {

class ProjectorLight {
public:
    // levels: the projector's size, drive levels in [0, 1]. Throws std::invalid_argument for
    // another size. windowStart: where the camera's exposure window starts in the frame
    // (dlp_timing.h), used when the projector's DLP timing is on; without it, or with the timing
    // off, each level gives its time-average.
    ProjectorLight(const SimulatedProjector& projector, const RgbImage& levels,
                   std::optional<double> windowStart = std::nullopt);

    // Relative output per channel at a projector image point (pixel centres at integers),
    // bilinear between pixel centres, clamped to the edge: a pixel's light is the Gaussian
    // defocus of its value convolved with the one-pixel tent of the interpolation.
    std::array<float, 3> at(float x, float y) const;

private:
    int width_ = 0, height_ = 0;
    std::vector<float> output_;  // width·height·3
};

}  // namespace vpe::renderer::procam
