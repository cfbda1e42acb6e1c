// SPDX-License-Identifier: MIT
// What a visitor sees: the white object lit by a projector pattern (simulation), and the
// material rendered directly — equal, where the pattern could be compensated, by design.
#pragma once

#include <cstdint>
#include <vector>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/render_scene.h"

namespace vpe::renderer {

// All images have the viewer camera's size.
struct SimulatedView {
    RgbImage radiance;   // linear radiance reaching the camera; 0 off the object
    MaskImage coverage;  // 1 where the pixel sees the object
    MaskImage lit;       // 1 where the projector reaches the point seen (not in its shadow)
    // Where the point seen falls in the projector image (pixel coordinates, distortion
    // applied), two floats per pixel; NaN where not lit.
    std::vector<float> projectorPixel;
};

struct DirectView {
    RgbImage radiance;   // L = gain · E_light · f, ≥ 0; 0 off the object
    MaskImage coverage;  // 1 where the pixel sees the object
};

// For every viewer pixel: the first hit X of its ray, the shading normal n there (on the
// viewer's side); the projector's centre C, d = |C − X|. X is lit when n·(C − X) > 0, X is in
// front of the projector, its projector pixel p lies in the image (within half a pixel of a
// pixel centre) and no triangle lies on the segment C → X (relative tolerance 1e-6: the
// projector's exact depth test). Lit: radiance = ρ/π·(S·r̄ + E_ambient) with
// S = projectorIrradianceScale and r̄ the bilinear interpolation at p of r(level) over the
// four nearest projector pixels (clamp to edge) — light is interpolated, not levels, as the
// projector's optics blur light. Not lit: ρ/π·E_ambient. Only scene.mesh, scene.projector and
// scene.surface are used. Throws std::invalid_argument when the pattern's size is not the
// projector's or the inputs are invalid.
SimulatedView simulateVisitorView(const RenderScene& scene, const RgbImage& pattern,
                                  const proto::PinholeCamera& viewerCamera,
                                  const RenderOptions& options = {});

// What a visitor sees of a show of several projectors on one object.
struct SimulatedShowView {
    RgbImage radiance;   // linear radiance reaching the camera; 0 off the object
    MaskImage coverage;  // 1 where the pixel sees the object
    // Bit i set where projector i reaches the point seen (in its image, facing it, not in its
    // shadow); 0: no projector does.
    ScalarImage<std::uint32_t> litBy;
    // Per projector: its share of the light at the point each pixel sees (its scene's
    // lightShare, bilinear at the point's projector pixel; 1 without one), 0 where it does not
    // reach the point.
    std::vector<FloatImage> shares;
};

// The combined light of several projectors — each scene's projector showing its pattern — on
// the white object (every scene's mesh and surface must be the first's: one object), seen from
// the viewer camera: ρ/π·(Σ_i S_i·r̄_i + E_ambient), each term as simulateVisitorView's, the
// room's light counted once. At most 32 projectors. Throws std::invalid_argument as
// simulateVisitorView does, or when the scenes and patterns do not pair up.
SimulatedShowView simulateShowView(const std::vector<const RenderScene*>& scenes,
                                   const std::vector<const RgbImage*>& patterns,
                                   const proto::PinholeCamera& viewerCamera,
                                   const RenderOptions& options = {});

// The material rendered directly from the viewer camera: as renderProjectorFrame's target,
// with the viewer at the camera's centre (scene.viewer is not used) and options.gain.
DirectView renderDirectView(const RenderScene& scene, const proto::PinholeCamera& viewerCamera,
                            const RenderOptions& options = {});

}  // namespace vpe::renderer
