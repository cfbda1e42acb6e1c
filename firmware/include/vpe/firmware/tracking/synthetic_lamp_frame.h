// SPDX-License-Identifier: MIT
// SyntheticLampFrame: a camera frame made up from a description — a dark, noisy room, dim
// distractors, the lamp as a bright Gaussian spot. Tests render them to know where the lamp
// truly is; `vpe-player --replay` renders them from {"type":"camera","x","y","radius"} lines
// so the real decoding path (LampTracker) runs without a camera.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "vpe/firmware/tracking/luminance_frame.h"

namespace vpe::firmware {

// A spot peak · exp(−d² / 2σ²) with σ = radius, centred on (x, y) in pixels (pixel centres at
// integers). A peak above 255 saturates the spot's core as a real lamp does.
struct SyntheticSpot {
    double x = 0.0;
    double y = 0.0;
    double radius = 3.0;
    double peak = 255.0;
};

struct SyntheticLampFrame {
    int width = 320;
    int height = 240;
    double background = 16.0;  // the room's mean level
    double noiseSigma = 2.0;   // Gaussian noise on every pixel (0: none)
    std::uint32_t seed = 1;    // the noise is a pure function of the seed (mt19937, Box–Muller)
    std::optional<SyntheticSpot> lamp;
    std::vector<SyntheticSpot> distractors;  // glints, lit surfaces: usually dim or small

    // Throws std::invalid_argument, one line naming the field, for a size outside
    // 1…4096 × 1…4096, a non-finite position, a radius outside (0, 4096], or a level (peak,
    // background, noise) beyond 1e6 (replay files are input too).
    LuminanceFrame render() const;
};

}  // namespace vpe::firmware
