// SPDX-License-Identifier: MIT
// The GLES renderer's frames against the CPU reference with the bundle's full-precision
// coefficients (exact Fourier evaluation, no θs basis), under the reference lights: what a
// visitor would see changed by the device's shortcuts, as 8-bit PSNR. Shared by
// vpe_gles_fidelity (the demo bundle) and the GPU fidelity test (a small baked vase).
#pragma once

#include <string>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::testing {

struct GpuFidelity {
    std::string light;
    double gain = 1;          // the reference's --gain auto (0.5% of its pixels clipped)
    std::size_t covered = 0;  // pixels that see the object
    double psnrObject = 0;    // over the object's pixels (all channels)
    double psnrFrame = 0;     // over the whole frame
    int largest = 0;          // the largest difference, levels
};

// One entry per reference light (support/reference_lights.h), in their order. A GL ES 3.1
// context of `platform` must be current.
std::vector<GpuFidelity> measureGpuFidelity(const proto::BundleView& bundle,
                                            renderer::gles::GraphicsPlatform& platform,
                                            const std::string& preset = "");

}  // namespace vpe::testing
