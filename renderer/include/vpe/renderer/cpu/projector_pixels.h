// SPDX-License-Identifier: MIT
// ProjectorPixels: what each projector pixel sees — fixed for a mesh and a projector, so traced
// once: the exact ray of the pixel (undistorted pixel centre), its nearest hit, the surface
// there and the projector's irradiance scale S. The CPU reference renders every frame from it
// and the GLES renderer uploads it once as its geometry buffer: both read this one definition,
// so their silhouettes agree by construction.
#pragma once

#include <limits>
#include <memory>
#include <optional>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/projector_model.h"
#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/surface_point.h"

namespace vpe::renderer {

// A covered pixel: the surface its ray hits and S = P·max(cos θp, 0)/d² there
// (projectorIrradianceScale, with the shading normal), and the share s of the light wanted
// there that this projector gives (bundle 1.5's blend; 1 when it is the only one).
struct ProjectorPixel {
    SurfacePoint point;
    double irradianceScale = 0;
    double share = 1;

    // What the compensation divides by: S / s, so that the projector aims for s of the light
    // above the floor and the shares of every projector add up to all of it. s = 0: +∞ (asks
    // nothing of this projector); S = 0 < s: 0 (any light asked of it clips).
    double compensationScale() const {
        return share > 0 ? irradianceScale / share : std::numeric_limits<double>::infinity();
    }
};

class ProjectorPixels {
public:
    // Builds the ray caster over the mesh (it must pass checkRenderMesh) for this projector.
    // The mesh's arrays must outlive this object (their uvs and normals are read per pixel).
    // `share`: the projector's share of the light per pixel (the projector's size), or none.
    // Throws std::invalid_argument when the share map is not the projector's size.
    ProjectorPixels(const RenderMesh& mesh, const ProjectorModel& projector,
                    std::shared_ptr<const FloatImage> share = nullptr);

    // Pixel (x, y) (row 0 the top row): what its ray hits, or nothing. Thread-safe.
    std::optional<ProjectorPixel> trace(int x, int y) const;

    int width() const { return projector_.camera.width; }
    int height() const { return projector_.camera.height; }

private:
    RayCaster caster_;
    RenderMesh mesh_;
    ProjectorModel projector_;
    Vec3d origin_;
    std::shared_ptr<const FloatImage> share_;
};

}  // namespace vpe::renderer
