// SPDX-License-Identifier: MIT
// The lights the accuracy measurements render the demo vase under — around it, two grazing
// ones and one behind it — and how a frame's levels differ from a reference's: what
// vpe_theta_basis_curve, vpe_gles_fidelity and the GPU fidelity test share.
#pragma once

#include <cstddef>
#include <span>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/projector_frame.h"

namespace vpe::testing {

struct ReferenceLight {
    const char* name;
    renderer::Vec3d position;  // object frame, metres; the demo vase stands on the origin
};

// Around the vase, the projector and viewer at +z. "over" and "under" rake across it from
// above and below behind it: of the surface they light (the shoulder, the lower body), they
// light much from at most 5° above its horizon. "behind" lights only the rim of the
// silhouette, which the horizon factor fades.
std::span<const ReferenceLight> referenceLights();

// Of the mesh vertices the projector and the viewer both see, the share a light reaches, and
// of those the share it reaches from at most kGrazingDegrees above their horizon (occlusion
// ignored): how grazing a light is.
inline constexpr double kGrazingDegrees = 5.0;
struct GrazingShare {
    double lit = 0, grazing = 0;
};
GrazingShare grazingShare(const proto::BundleView& bundle, const renderer::Vec3d& light);

// The 8-bit levels (as the projector shows them) of a frame against a reference: squared
// differences over the values of the pixels the reference covers and over the whole frame,
// and those of the levels before quantization (on the object).
struct LevelError {
    double squared8 = 0, squared8Frame = 0, squaredLevels = 0;
    std::size_t count = 0, frameCount = 0;
    int largest8 = 0;
};
LevelError levelError(const renderer::ProjectorFrame& reference,
                      std::span<const float> levels);  // 3 per pixel, as reference.level
// The same for an RGBA8 frame read back from a GPU (4 bytes per pixel, rows from the top).
LevelError levelError(const renderer::ProjectorFrame& reference,
                      std::span<const std::uint8_t> rgba);

// PSNR for a peak of 255 (8-bit) or 1 (levels); +∞ for identical frames.
double psnr(double squared, std::size_t count, double peak);

}  // namespace vpe::testing
