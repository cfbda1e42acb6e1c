// SPDX-License-Identifier: MIT
// PinholeCamera: OpenCV's camera model with its five-coefficient lens distortion, for the
// projector (distorted) and for a viewer's camera (usually not), and the maps between object
// points, ideal (undistorted) normalized coordinates and pixels.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "vpe/proto/bundle_contents.h"
#include "vpe/proto/vector_types.h"

namespace vpe::proto {

// A point X of the object frame (metres) is x = R·X + T in the camera frame (x right, y down,
// z forward: the camera looks along +z). Its ideal normalized coordinates are
// (a, b) = (x/z, y/z); OpenCV's distortion turns them into (a', b') (distortNormalized), and
// the pixel is (fx·a' + s·b' + cx, fy·b' + cy) with K = [fx s cx; 0 fy cy; 0 0 1]. Pixel
// centres sit at integer coordinates: pixel (0, 0) covers [−0.5, 0.5]², row 0 is the top row.
// The same conventions as the bundle's ProjectorCalibration (cameraOf below); offline/scene's
// projector calibration is this type.
struct PinholeCamera {
    int width = 0, height = 0;                           // pixels
    std::array<double, 9> K{};                           // row-major intrinsics
    std::array<double, 5> distortion{};                  // k1, k2, p1, p2, k3 (OpenCV order)
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, object → camera
    std::array<double, 3> T{};                           // metres

    Vec3d center() const;                           // −Rᵀ·T, object frame
    Vec3d toCamera(const Vec3d& point) const;       // R·X + T
    Vec3d directionToObject(const Vec3d& d) const;  // Rᵀ·d
};

// Why the camera cannot be used, as a phrase; "" when it can: size 1..16384, finite numbers,
// fx, fy > 0, K's bottom row (0, 0, 1), R a rotation within 1e-6.
std::string checkCamera(const PinholeCamera& camera);

// OpenCV's distortion of ideal normalized coordinates:
//   r² = a² + b², radial = 1 + k1 r² + k2 r⁴ + k3 r⁶,
//   a' = a·radial + 2 p1 a b + p2 (r² + 2a²),  b' = b·radial + p1 (r² + 2b²) + 2 p2 a b.
Vec2d distortNormalized(const std::array<double, 5>& distortion, const Vec2d& ideal);

// The inverse, by cv::undistortPoints' fixed-point iteration
//   (a, b) ← ((a' − Δa(a, b)) / radial(a, b), (b' − Δb(a, b)) / radial(a, b))
// from (a, b) = (a', b'), run until the reprojection error is below 1e-13 (normalized units,
// ~1e-10 px) or 200 iterations (OpenCV's default stops after 5, too early for a reference).
Vec2d undistortNormalized(const std::array<double, 5>& distortion, const Vec2d& distorted);

// Pixel → distorted normalized coordinates (K⁻¹, skew included) and back.
Vec2d pixelToNormalized(const PinholeCamera& camera, const Vec2d& pixel);
Vec2d normalizedToPixel(const PinholeCamera& camera, const Vec2d& normalized);

// The ray through a pixel (undistorted): direction in the object frame, not unit length —
// it is Rᵀ·(a, b, 1), so the ray parameter t is the camera-frame depth z. Origin: center().
Vec3d pixelRayDirection(const PinholeCamera& camera, const Vec2d& pixel);

// The pixel that shows X (distortion applied), or nothing when X is not in front of the
// camera (z ≤ 0). The pixel may lie outside the image.
std::optional<Vec2d> projectToPixel(const PinholeCamera& camera, const Vec3d& point);

// A distortion-free camera at `eye` aimed at `target`, image rows parallel to the horizontal
// plane (world up is +y), square pixels, principal point at the image centre
// ((width − 1)/2, (height − 1)/2). offline/scene's projectorLookingAt is this. Throws
// std::invalid_argument for a field of view outside (0, 180), eye = target, or looking
// straight up or down.
PinholeCamera cameraLookingAt(int width, int height, double verticalFovDegrees, const Vec3d& eye,
                              const Vec3d& target);

// The camera of a bundle's projector (or of its camera, format 1.3: the same table): the one
// place where the bundle's field names (intrinsics, rotation, translation) become the camera's
// (K, R, T). Values are copied as they are; checkProjector and checkBundleCamera
// (bundle_contents.h) are what refuse bad ones.
PinholeCamera cameraOf(const ProjectorCalibration& calibration);

}  // namespace vpe::proto
