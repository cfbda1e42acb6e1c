// SPDX-License-Identifier: MIT
// Roofline frame-rate estimates on the Raspberry Pi GPUs (docs/pi-headroom.md's peaks).
#pragma once

#include <string>

#include "shader_cost.h"

namespace vpe::shader_cost {

struct GpuPeaks {
    std::string name;
    double aluFlops = 0;        // FLOPs per second, both ALUs of every QPU lane busy
    double textureLookups = 0;  // texture lookups per second (assumed, not published)
};

// V3D 4.2: 8 QPUs × 4 lanes × 2 ALUs × 500 MHz; TMU 2 slices × 500 MHz, one lookup a clock.
GpuPeaks raspberryPi4();
// V3D 7.1: 16 QPUs × 4 lanes × 2 ALUs × 960 MHz; TMU 4 slices × 960 MHz, one lookup a clock.
GpuPeaks raspberryPi5();

struct FrameWorkload {
    double shadedPixels = 1.87e6;  // 1920 × 1080 at 90% coverage
    double aluEfficiency = 0.5;    // fraction of the ALU peak a real shader reaches
};

struct FrameEstimate {
    double aluSeconds = 0;
    double textureSeconds = 0;
    double framesPerSecond = 0;  // 1 / max(ALU time, TMU time)
};

// ALU time = pixels × flop_eq / (peak × efficiency); TMU time = pixels × fetches / lookup rate.
FrameEstimate estimateFrame(const ShaderCost& perPixel, const GpuPeaks& gpu,
                            const FrameWorkload& workload);

}  // namespace vpe::shader_cost
