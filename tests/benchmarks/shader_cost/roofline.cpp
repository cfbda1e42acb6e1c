// SPDX-License-Identifier: MIT
// Roofline estimates: the slowest of the ALU, the texture unit and memory bounds the frame.
#include "roofline.h"

#include <algorithm>
#include <limits>

namespace vpe::shader_cost {

namespace {

// sci-pi.org.uk/bench/stream.html: STREAM (gcc -O3, one thread) on a Pi 4, copy 5527 MB/s
// headless, 5160 MB/s while the Pi drove a 1920 × 1080 60 Hz display. The wire rate of its
// LPDDR4-3200 on a 32-bit bus is 12.8 GB/s.
constexpr double kPi4StreamCopy = 5160e6;
constexpr double kPi4WireRate = 3200e6 * 4;
// The Pi 5's LPDDR4X-4267 on the same 32-bit bus (Raspberry Pi's product brief): 17.1 GB/s wire
// rate. No STREAM figure for it was found; the Pi 4's ratio of STREAM to wire rate is assumed.
constexpr double kPi5WireRate = 4267e6 * 4;

double rate(double work, double perSecond) {
    return work > 0 ? work / perSecond : 0;
}

}  // namespace

GpuPeaks raspberryPi4() {
    return {"Pi 4 (V3D 4.2)", 8.0 * 4 * 2 * 500e6, 2 * 500e6, kPi4StreamCopy,
            "STREAM copy with a 1080p60 display, sci-pi.org.uk"};
}

GpuPeaks raspberryPi5() {
    return {"Pi 5 (V3D 7.1)", 16.0 * 4 * 2 * 960e6, 4 * 960e6,
            kPi5WireRate * (kPi4StreamCopy / kPi4WireRate),
            "LPDDR4X-4267 x 32 bit at the Pi 4's STREAM/wire ratio (derived)"};
}

FrameEstimate estimateFrame(const ShaderCost& perPixel, const GpuPeaks& gpu,
                            const FrameWorkload& workload) {
    FrameEstimate estimate;
    const double pixels = workload.shadedPixels;
    estimate.aluSeconds = rate(pixels * static_cast<double>(perPixel.flopEquivalent()),
                               gpu.aluFlops * workload.aluEfficiency);
    estimate.textureSeconds =
        rate(pixels * static_cast<double>(perPixel.textureFetches), gpu.textureLookups);
    estimate.memorySeconds = rate(pixels * static_cast<double>(perPixel.memoryBytes()),
                                  gpu.memoryBytes * workload.memoryShare);
    const auto fps = [](double seconds) {
        return seconds > 0 ? 1.0 / seconds : std::numeric_limits<double>::infinity();
    };
    estimate.computeFramesPerSecond = fps(std::max(estimate.aluSeconds, estimate.textureSeconds));
    estimate.memoryFramesPerSecond = fps(estimate.memorySeconds);
    estimate.framesPerSecond =
        std::min(estimate.computeFramesPerSecond, estimate.memoryFramesPerSecond);
    return estimate;
}

}  // namespace vpe::shader_cost
