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
    // Memory bytes per second the board sustains (a published STREAM copy rate, or where none
    // is published the stated derivation; read and write bytes both count, as STREAM counts).
    double memoryBytes = 0;
    std::string memorySource;  // where memoryBytes comes from
};

// V3D 4.2: 8 QPUs × 4 lanes × 2 ALUs × 500 MHz; TMU 2 slices × 500 MHz, one lookup a clock;
// memory: STREAM copy on a Pi 4 driving a 1080p60 display, 5160 MB/s (sci-pi.org.uk).
GpuPeaks raspberryPi4();
// V3D 7.1: 16 QPUs × 4 lanes × 2 ALUs × 960 MHz; TMU 4 slices × 960 MHz, one lookup a clock;
// memory: the Pi 4's STREAM share of its wire rate applied to LPDDR4X-4267 (derived, see .cpp).
GpuPeaks raspberryPi5();

struct FrameWorkload {
    double shadedPixels = 1.87e6;  // 1920 × 1080 at 90% coverage
    double aluEfficiency = 0.5;    // fraction of the ALU peak a real shader reaches
    // Fraction of the board's memory rate the GPU gets while the frame renders (an assumption:
    // the player's CPU waits on page flips; the display's scanout is already in the figure).
    double memoryShare = 1.0;
};

struct FrameEstimate {
    double aluSeconds = 0;
    double textureSeconds = 0;
    double memorySeconds = 0;
    double computeFramesPerSecond = 0;  // 1 / max(ALU time, TMU time): operations only
    double memoryFramesPerSecond = 0;   // 1 / memory time: bytes only
    double framesPerSecond = 0;         // the lower of the two
};

// ALU time = pixels × flop_eq / (peak × efficiency); TMU time = pixels × fetches / lookup rate;
// memory time = pixels × (bytes read + written) / (memory rate × share).
FrameEstimate estimateFrame(const ShaderCost& perPixel, const GpuPeaks& gpu,
                            const FrameWorkload& workload);

}  // namespace vpe::shader_cost
