// SPDX-License-Identifier: MIT
// SurfaceGeometry: per-pixel normal, surface point and view direction of a capture, from
// its camera, a normal map and (for point lights or a pinhole camera) a position map or a
// plane.
#pragma once

#include <optional>

#include "capture/capture.h"
#include "image/image_file.h"
#include "normals/normal_map.h"

namespace vpe {

class SurfaceGeometry {
public:
    // `normals` must match the capture's image size. Loads the position map if there is one.
    SurfaceGeometry(const Capture& capture, NormalMap normals);

    int width() const { return normals_.width; }
    int height() const { return normals_.height; }
    const NormalMap& normals() const { return normals_; }
    bool valid(int x, int y) const { return normals_.valid[normals_.index(x, y)] != 0; }
    Vec3d normal(int x, int y) const;
    Vec3d position(int x, int y) const;  // world coordinates
    Vec3d toViewer(int x, int y) const;  // unit vector from the surface point to the camera

private:
    CameraModel camera_;
    std::optional<SurfacePlane> plane_;
    NormalMap normals_;
    std::optional<FloatImage> positions_;
};

}  // namespace vpe
