// SPDX-License-Identifier: MIT
// exposeSensor: what a simulated camera's sensor and pipeline make of the light on its pixels.
#pragma once

#include <cstdint>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/procam/procam_simulator.h"

namespace vpe::renderer::procam {

// Per pixel and channel: signal s = exposure × radiance (monochrome: of the Rec. 709
// luminance), electrons e = s·full well plus a Gaussian of variance e (shot noise; Poisson's
// normal limit, exact enough above a few electrons) and σ = read noise, back to s, clipped to
// [0, 1], through the response, rounded to 2^bits − 1 levels. The noise is a pure function of
// (seed, frame, pixel, channel), so a frame is the same on any number of threads.
CameraFrame exposeSensor(const SimulatedCamera& camera, const RgbImage& radiance,
                         std::uint64_t frame, int threads);

}  // namespace vpe::renderer::procam
