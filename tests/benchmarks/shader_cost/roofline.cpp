// SPDX-License-Identifier: MIT
// Roofline estimates: the slower of the ALU and the texture unit bounds the frame.
#include "roofline.h"

#include <algorithm>
#include <limits>

namespace vpe::shader_cost {

GpuPeaks raspberryPi4() {
    return {"Pi 4 (V3D 4.2)", 8.0 * 4 * 2 * 500e6, 2 * 500e6};
}

GpuPeaks raspberryPi5() {
    return {"Pi 5 (V3D 7.1)", 16.0 * 4 * 2 * 960e6, 4 * 960e6};
}

FrameEstimate estimateFrame(const ShaderCost& perPixel, const GpuPeaks& gpu,
                            const FrameWorkload& workload) {
    FrameEstimate estimate;
    estimate.aluSeconds = workload.shadedPixels * static_cast<double>(perPixel.flopEquivalent()) /
                          (gpu.aluFlops * workload.aluEfficiency);
    estimate.textureSeconds =
        workload.shadedPixels * static_cast<double>(perPixel.textureFetches) / gpu.textureLookups;
    const double frameSeconds = std::max(estimate.aluSeconds, estimate.textureSeconds);
    estimate.framesPerSecond =
        frameSeconds > 0 ? 1.0 / frameSeconds : std::numeric_limits<double>::infinity();
    return estimate;
}

}  // namespace vpe::shader_cost
