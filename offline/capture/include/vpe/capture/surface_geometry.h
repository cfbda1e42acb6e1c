// SPDX-License-Identifier: MIT
// SurfaceGeometry: per-pixel surface point and view direction of a capture, from its camera
// and (for point lights or a pinhole camera) a position map or a plane. Normals are a
// separate input (NormalMap): several camera hypotheses can share one normal map.
#pragma once

#include <optional>

#include "vpe/capture/capture.h"
#include "vpe/image/image_file.h"

namespace vpe::capture {

class SurfaceGeometry {
public:
    // Loads the position map if there is one; it must be width × height.
    SurfaceGeometry(const Capture& capture, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    Vec3d position(int x, int y) const;  // world coordinates
    Vec3d toViewer(int x, int y) const;  // unit vector from the surface point to the camera

private:
    CameraModel camera_;
    std::optional<SurfacePlane> plane_;
    int width_;
    int height_;
    std::optional<image::FloatImage> positions_;
};

}  // namespace vpe::capture
