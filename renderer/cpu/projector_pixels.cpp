// SPDX-License-Identifier: MIT
// ProjectorPixels: one exact ray per projector pixel (see the header).
#include "vpe/renderer/projector_pixels.h"

#include "vpe/renderer/lambertian_screen.h"

namespace vpe::renderer {

ProjectorPixels::ProjectorPixels(const RenderMesh& mesh, const ProjectorModel& projector)
    : caster_(mesh), mesh_(mesh), projector_(projector), origin_(projector.camera.center()) {}

std::optional<ProjectorPixel> ProjectorPixels::trace(int x, int y) const {
    const Vec3d direction =
        pixelRayDirection(projector_.camera, {static_cast<double>(x), static_cast<double>(y)});
    const auto hit = caster_.closestHit(origin_, direction);
    if (!hit) {
        return std::nullopt;
    }
    ProjectorPixel pixel;
    pixel.point = surfacePoint(mesh_, origin_, direction, *hit);
    pixel.irradianceScale =
        projectorIrradianceScale(projector_, pixel.point.position, pixel.point.normal);
    return pixel;
}

}  // namespace vpe::renderer
