// SPDX-License-Identifier: MIT
// OpenCV's pinhole camera with distortion, and its inverse after cv::undistortPoints.
#include "vpe/proto/pinhole_camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vpe::proto {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxResolution = 16384;
constexpr double kRotationTolerance = 1e-6;
// Undistortion stops when distorting the estimate reproduces the input to this (normalized
// units: ~1e-10 px for focal lengths of a few thousand pixels).
constexpr double kUndistortTolerance = 1e-13;
constexpr int kUndistortMaxIterations = 200;

}  // namespace

Vec3d PinholeCamera::center() const {
    // −Rᵀ·T
    return {-(R[0] * T[0] + R[3] * T[1] + R[6] * T[2]), -(R[1] * T[0] + R[4] * T[1] + R[7] * T[2]),
            -(R[2] * T[0] + R[5] * T[1] + R[8] * T[2])};
}

Vec3d PinholeCamera::toCamera(const Vec3d& p) const {
    return {R[0] * p.x + R[1] * p.y + R[2] * p.z + T[0],
            R[3] * p.x + R[4] * p.y + R[5] * p.z + T[1],
            R[6] * p.x + R[7] * p.y + R[8] * p.z + T[2]};
}

Vec3d PinholeCamera::directionToObject(const Vec3d& d) const {
    return {R[0] * d.x + R[3] * d.y + R[6] * d.z, R[1] * d.x + R[4] * d.y + R[7] * d.z,
            R[2] * d.x + R[5] * d.y + R[8] * d.z};
}

std::string checkCamera(const PinholeCamera& camera) {
    if (camera.width < 1 || camera.width > kMaxResolution || camera.height < 1 ||
        camera.height > kMaxResolution) {
        return "size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
               " is outside 1..16384";
    }
    const auto finite = [](const auto& values) {
        return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    };
    if (!finite(camera.K) || !finite(camera.distortion) || !finite(camera.R) || !finite(camera.T)) {
        return "K, distortion, R and T must be finite";
    }
    const auto& K = camera.K;
    if (!(K[0] > 0) || !(K[4] > 0)) {
        return "K: focal lengths must be positive";
    }
    if (K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1) {
        return "K: bottom rows must be (0, fy, cy), (0, 0, 1)";
    }
    const auto& R = camera.R;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double rowDot =
                R[3 * i] * R[3 * j] + R[3 * i + 1] * R[3 * j + 1] + R[3 * i + 2] * R[3 * j + 2];
            if (std::abs(rowDot - (i == j ? 1.0 : 0.0)) > kRotationTolerance) {
                return "R is not orthonormal";
            }
        }
    }
    const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                       R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (det < 0) {
        return "R is a reflection (determinant −1), not a rotation";
    }
    return "";
}

Vec2d distortNormalized(const std::array<double, 5>& distortion, const Vec2d& ideal) {
    const auto& [k1, k2, p1, p2, k3] = distortion;
    const double a = ideal.x, b = ideal.y;
    const double r2 = a * a + b * b;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    return {a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a),
            b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b};
}

Vec2d undistortNormalized(const std::array<double, 5>& distortion, const Vec2d& distorted) {
    const auto& [k1, k2, p1, p2, k3] = distortion;
    if (k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0) {
        return distorted;
    }
    // cv::undistortPoints (cvUndistortPointsInternal): x ← (x0 − Δ(x)) / radial(x), with its
    // EPS criterion measured, as there, by distorting the estimate again.
    Vec2d x = distorted;
    for (int iteration = 0; iteration < kUndistortMaxIterations; ++iteration) {
        const double r2 = x.x * x.x + x.y * x.y;
        const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
        if (!(radial > 0)) {
            // Past the radius where the model folds over: no inverse; OpenCV gives up the same
            // way and returns the input.
            return distorted;
        }
        const double deltaX = 2 * p1 * x.x * x.y + p2 * (r2 + 2 * x.x * x.x);
        const double deltaY = p1 * (r2 + 2 * x.y * x.y) + 2 * p2 * x.x * x.y;
        x = {(distorted.x - deltaX) / radial, (distorted.y - deltaY) / radial};
        const Vec2d again = distortNormalized(distortion, x);
        if (std::hypot(again.x - distorted.x, again.y - distorted.y) < kUndistortTolerance) {
            break;
        }
    }
    return x;
}

Vec2d pixelToNormalized(const PinholeCamera& camera, const Vec2d& pixel) {
    const auto& K = camera.K;
    const double b = (pixel.y - K[5]) / K[4];
    return {(pixel.x - K[2] - K[1] * b) / K[0], b};
}

Vec2d normalizedToPixel(const PinholeCamera& camera, const Vec2d& n) {
    const auto& K = camera.K;
    return {K[0] * n.x + K[1] * n.y + K[2], K[4] * n.y + K[5]};
}

Vec3d pixelRayDirection(const PinholeCamera& camera, const Vec2d& pixel) {
    const Vec2d ideal = undistortNormalized(camera.distortion, pixelToNormalized(camera, pixel));
    return camera.directionToObject({ideal.x, ideal.y, 1.0});
}

std::optional<Vec2d> projectToPixel(const PinholeCamera& camera, const Vec3d& point) {
    const Vec3d x = camera.toCamera(point);
    if (!(x.z > 0)) {
        return std::nullopt;
    }
    return normalizedToPixel(camera, distortNormalized(camera.distortion, {x.x / x.z, x.y / x.z}));
}

PinholeCamera cameraLookingAt(int width, int height, double verticalFovDegrees, const Vec3d& eye,
                              const Vec3d& target) {
    if (!(verticalFovDegrees > 0 && verticalFovDegrees < 180)) {
        throw std::invalid_argument("camera: vertical field of view must be in (0, 180) degrees");
    }
    const Vec3d toTarget{target.x - eye.x, target.y - eye.y, target.z - eye.z};
    if (!(dot(toTarget, toTarget) > 0)) {
        throw std::invalid_argument("camera: the eye and the target coincide");
    }
    const Vec3d forward = normalized(toTarget);
    const Vec3d side{-forward.z, 0, forward.x};  // forward × (0, 1, 0)
    if (!(dot(side, side) > 1e-12)) {
        throw std::invalid_argument(
            "camera: looking straight up or down leaves the image rows undefined");
    }
    const Vec3d right = normalized(side);
    const Vec3d down = cross(forward, right);
    PinholeCamera c;
    c.width = width;
    c.height = height;
    const double focal = 0.5 * height / std::tan(0.5 * verticalFovDegrees * kPi / 180);
    c.K = {focal, 0, 0.5 * (width - 1), 0, focal, 0.5 * (height - 1), 0, 0, 1};
    c.R = {right.x, right.y, right.z, down.x, down.y, down.z, forward.x, forward.y, forward.z};
    for (std::size_t i = 0; i < 3; ++i) {
        c.T[i] = -(c.R[3 * i] * eye.x + c.R[3 * i + 1] * eye.y + c.R[3 * i + 2] * eye.z);
    }
    return c;
}

PinholeCamera cameraOf(const ProjectorCalibration& calibration) {
    PinholeCamera camera;
    camera.width = static_cast<int>(calibration.width);
    camera.height = static_cast<int>(calibration.height);
    camera.K = calibration.intrinsics;
    camera.distortion = calibration.distortion;
    camera.R = calibration.rotation;
    camera.T = calibration.translation;
    return camera;
}

}  // namespace vpe::proto
