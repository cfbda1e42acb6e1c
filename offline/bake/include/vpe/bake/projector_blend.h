// SPDX-License-Identifier: MIT
// ProjectorBlend: several projectors on one object (bundle format 1.5's blend). Per projector
// pixel, the share of the light wanted at the surface point it lights that this projector
// gives: the shares of every projector that reaches a point add up to 1, favour the projector
// that sees it best, and fade to 0 towards the edges of what each projector reaches, so that no
// step shows where one takes over from another (docs/multi-projector.md).
#pragma once

#include <vector>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/projector_model.h"
#include "vpe/renderer/cpu/render_mesh.h"

namespace vpe::bake {

struct BlendOptions {
    // Width of the fade at the edge of a projector's reach, in its pixels; 0: 8% of its
    // shorter side (86 pixels at 1080p).
    double featherPixels = 0;
    // Size of the surface-coverage picture (texture space, u across, v up the rows' reverse).
    int coverageWidth = 512, coverageHeight = 256;
    int threads = 0;
};

// How well projector j lights a point X with normal n, before the fade at its edges:
//   q = cos²θ · (f / d)²
// f/d: projector pixels per metre on a surface facing it (resolution, and the 1/d² of the
// irradiance up to a constant); one cos θ for the pixels' area on the surface, one for the
// irradiance's fall-off at incidence (a grazing projector also errs most with geometry).
double projectionQuality(const renderer::ProjectorModel& projector, const renderer::Vec3d& point,
                         const renderer::Vec3d& normal);

struct ProjectorBlend {
    // One per projector, its size: the share s ∈ [0, 1] at each pixel (0 where it sees nothing).
    std::vector<renderer::FloatImage> shares;
    // The object's surface in texture space: per texel, the number of projectors that reach it
    // (255 off the surface).
    renderer::ScalarImage<std::uint8_t> reach;
    // Of the surface's area: reached by no projector, and by two or more.
    double unreachedShare = 0, overlapShare = 0;
};

// The blend of `projectors` on `mesh` (object frame, the renderer's uv convention). A point is
// reached by projector j when it lies in j's image, faces it, and no triangle lies between
// (the visitor view's test). Its weight there is q_j · (ε + fade_j), fade_j a smoothstep of the
// distance from the edge of j's reach in j's image (its image border, the object's silhouette
// and depth steps in it), ε = 1e-3 so that a point only one projector reaches still gets all of
// its light; the shares are the weights normalized. Throws std::invalid_argument when the mesh
// or a projector cannot be rendered.
ProjectorBlend blendProjectors(const renderer::RenderMesh& mesh,
                               const std::vector<renderer::ProjectorModel>& projectors,
                               const BlendOptions& options = {});

}  // namespace vpe::bake
