// SPDX-License-Identifier: MIT
// renderProjectorFrame: the image the projector must show so that, seen from the viewer, the
// white object looks like the material under the virtual light. The CPU reference.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/projector_pixels.h"
#include "vpe/renderer/cpu/render_scene.h"

namespace vpe::renderer {

struct ProjectorFrameStats {
    std::size_t coveredPixels = 0;      // projector pixels that see the object
    std::size_t clippedPixels = 0;      // of those, with some channel clipped (either end)
    std::size_t clippedHighPixels = 0;  // some channel needs more than full output
    std::size_t clippedLowPixels = 0;   // some channel needs less than the black level
    double clippedFraction = 0;         // clippedPixels / coveredPixels (0 when none covered)
    double gain = 1;                    // the gain the frame was rendered with
};

// Flags of ProjectorFrame::clipped.
inline constexpr std::uint8_t kClippedHigh = 1;  // some channel needs more than full output
inline constexpr std::uint8_t kClippedLow = 2;   // some channel needs less than the black level

// All images have the projector's size; row 0 is the projector's top row.
struct ProjectorFrame {
    RgbImage level;           // drive levels in [0, 1], linear (before 8-bit quantization)
    RgbImage targetRadiance;  // L toward the viewer, ≥ 0, gain included; 0 off the object
    MaskImage coverage;       // 1 where the pixel's ray hits the object
    MaskImage clipped;        // kClippedHigh | kClippedLow where some channel clipped, else 0
    // compensatePixel's gainLimit rounded down to a float (so that rendering at this gain
    // does not clip the pixel at the top); +∞ off the object or where no channel wants light.
    FloatImage gainLimit;
    ProjectorFrameStats stats;
};

// For every projector pixel (x, y): the ray through its centre (undistorted), its first hit X
// on the mesh, the shading normal and uv there (surface_point.h); the target radiance
//   L = gain · E_light(X) · f(θd, θs),  negative channels clamped to 0,
// with f the region-blended material at uv (material_textures.h), n the shading normal,
// l = normalize(light − X), v = normalize(viewer − X); then compensatePixel with
// S = projectorIrradianceScale(X, n). Pixels that see nothing get level 0.
// Throws std::invalid_argument naming the problem when checkRenderScene fails or the gain is
// not positive.
ProjectorFrame renderProjectorFrame(const RenderScene& scene, const RenderOptions& options = {});

// The same frame from pixels already traced for the scene's mesh and projector (what a frame
// does not recompute: frames for many lights trace once).
ProjectorFrame renderProjectorFrame(const RenderScene& scene, const ProjectorPixels& pixels,
                                    const RenderOptions& options = {});

// The largest gain g ≤ 1 at which at most maxClippedFraction of the covered pixels clip at the
// top (need more than full output): the ⌊q·N⌋-th smallest gainLimit of the N covered pixels
// (0-based), capped at 1. E.g. q = 0.005 puts the 99.5th percentile of the required output at
// full output. Clipping at the black level (ambient light above the target) is not counted: a
// lower gain only makes it worse. Render again with options.gain = g to apply it.
double gainForClippedFraction(const ProjectorFrame& frame, double maxClippedFraction);

}  // namespace vpe::renderer
