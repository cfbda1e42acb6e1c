// SPDX-License-Identifier: MIT
// ProjectorPixels: one exact ray per projector pixel (see the header).
#include "vpe/renderer/cpu/projector_pixels.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "vpe/renderer/cpu/lambertian_screen.h"

namespace vpe::renderer {

ProjectorPixels::ProjectorPixels(const RenderMesh& mesh, const ProjectorModel& projector,
                                 std::shared_ptr<const FloatImage> share)
    : caster_(mesh),
      mesh_(mesh),
      projector_(projector),
      origin_(projector.camera.center()),
      share_(std::move(share)) {
    if (share_ &&
        (share_->width != projector.camera.width || share_->height != projector.camera.height)) {
        throw std::invalid_argument(
            "ProjectorPixels: a share map of " + std::to_string(share_->width) + "x" +
            std::to_string(share_->height) + " for a projector of " +
            std::to_string(projector.camera.width) + "x" + std::to_string(projector.camera.height));
    }
}

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
    if (share_) {
        pixel.share = static_cast<double>(share_->at(x, y));
    }
    return pixel;
}

}  // namespace vpe::renderer
