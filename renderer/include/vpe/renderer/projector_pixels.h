// SPDX-License-Identifier: MIT
// ProjectorPixels: what each projector pixel sees — fixed for a mesh and a projector, so traced
// once: the exact ray of the pixel (undistorted pixel centre), its nearest hit, the surface
// there and the projector's irradiance scale S. The CPU reference renders every frame from it
// and the GLES renderer uploads it once as its geometry buffer: both read this one definition,
// so their silhouettes agree by construction.
#pragma once

#include <optional>

#include "vpe/renderer/projector_model.h"
#include "vpe/renderer/ray_caster.h"
#include "vpe/renderer/surface_point.h"

namespace vpe::renderer {

// A covered pixel: the surface its ray hits and S = P·max(cos θp, 0)/d² there
// (projectorIrradianceScale, with the shading normal).
struct ProjectorPixel {
    SurfacePoint point;
    double irradianceScale = 0;
};

class ProjectorPixels {
public:
    // Builds the ray caster over the mesh (it must pass checkRenderMesh) for this projector.
    // The mesh's arrays must outlive this object (their uvs and normals are read per pixel).
    ProjectorPixels(const RenderMesh& mesh, const ProjectorModel& projector);

    // Pixel (x, y) (row 0 the top row): what its ray hits, or nothing. Thread-safe.
    std::optional<ProjectorPixel> trace(int x, int y) const;

    int width() const { return projector_.camera.width; }
    int height() const { return projector_.camera.height; }

private:
    RayCaster caster_;
    RenderMesh mesh_;
    ProjectorModel projector_;
    Vec3d origin_;
};

}  // namespace vpe::renderer
