// SPDX-License-Identifier: MIT
// Per-pixel capture geometry.
#include "vpe/capture/surface_geometry.h"

#include <cmath>

#include "vpe/common/input_error.h"

namespace vpe::capture {

SurfaceGeometry::SurfaceGeometry(const Capture& capture, int width, int height)
    : camera_(capture.camera), plane_(capture.plane), width_(width), height_(height) {
    if (capture.positionMap) {
        positions_ = image::readImage(*capture.positionMap);
        if (positions_->channels < 3) {
            throw common::InputError(*capture.positionMap,
                                     "position map needs 3 channels (X, Y, Z)");
        }
        if (positions_->width != width_ || positions_->height != height_) {
            throw common::InputError(*capture.positionMap,
                                     "size " + std::to_string(positions_->width) + "x" +
                                         std::to_string(positions_->height) +
                                         " differs from the images' " + std::to_string(width_) +
                                         "x" + std::to_string(height_));
        }
    }
}

Vec3d SurfaceGeometry::position(int x, int y) const {
    if (positions_) {
        return {positions_->at(x, y, 0), positions_->at(x, y, 1), positions_->at(x, y, 2)};
    }
    if (const auto* ortho = std::get_if<OrthographicCamera>(&camera_)) {
        const double px = (x + 0.5 - width_ / 2.0) * ortho->pixelSize;
        const double py = (height_ / 2.0 - y - 0.5) * ortho->pixelSize;
        double pz = 0;
        if (plane_ && std::fabs(plane_->normal.z) > 1e-9) {
            pz = plane_->point.z - (plane_->normal.x * (px - plane_->point.x) +
                                    plane_->normal.y * (py - plane_->point.y)) /
                                       plane_->normal.z;
        }
        return {px, py, pz};
    }
    // Pinhole: intersect the pixel's ray with the plane (the manifest reader guarantees one).
    const auto& pinhole = std::get<PinholeCamera>(camera_);
    const auto& r = pinhole.rotation;
    const double cx = (x - pinhole.cx) / pinhole.fx;
    const double cy = (y - pinhole.cy) / pinhole.fy;
    const Vec3d direction{r[0] * cx + r[3] * cy + r[6], r[1] * cx + r[4] * cy + r[7],
                          r[2] * cx + r[5] * cy + r[8]};
    const Vec3d origin = pinhole.center();
    const SurfacePlane plane = plane_.value_or(SurfacePlane{});
    const double denominator = proto::dot(plane.normal, direction);
    const Vec3d toPlane{plane.point.x - origin.x, plane.point.y - origin.y,
                        plane.point.z - origin.z};
    const double t =
        std::fabs(denominator) > 1e-12 ? proto::dot(plane.normal, toPlane) / denominator : 0.0;
    return {origin.x + t * direction.x, origin.y + t * direction.y, origin.z + t * direction.z};
}

Vec3d SurfaceGeometry::toViewer(int x, int y) const {
    if (std::holds_alternative<OrthographicCamera>(camera_)) {
        return {0, 0, 1};
    }
    const Vec3d center = std::get<PinholeCamera>(camera_).center();
    const Vec3d p = position(x, y);
    return proto::normalized(Vec3d{center.x - p.x, center.y - p.y, center.z - p.z});
}

}  // namespace vpe::capture
