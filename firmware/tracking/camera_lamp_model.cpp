// SPDX-License-Identifier: MIT
// CameraLampModel: intrinsics scaled to the stream, then a ray–sphere intersection per position.
#include "vpe/firmware/tracking/camera_lamp_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace vpe::firmware {

namespace {

// How far the stream's aspect ratio may be from the calibration's: a few pixels of rounding in
// a sensor mode's size, not a crop.
constexpr double kAspectTolerance = 0.01;

std::string sizeText(int width, int height) {
    char text[64];
    std::snprintf(text, sizeof text, "%dx%d (aspect %.3f)", width, height,
                  static_cast<double>(width) / static_cast<double>(height));
    return text;
}

bool allFinite(const auto& values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

CameraLampModel::CameraLampModel(const proto::PinholeCamera& camera, int width, int height,
                                 const LightSphere& sphere, double radiusM)
    : calibratedCamera_(camera), streamCamera_(camera), sphere_(sphere), radiusM_(radiusM) {
    if (camera.width <= 0 || camera.height <= 0 || width <= 0 || height <= 0) {
        throw CalibrationError("camera model: sizes must be positive, got " +
                               std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                               " and " + std::to_string(width) + "x" + std::to_string(height));
    }
    if (!allFinite(camera.K) || !allFinite(camera.distortion) || !allFinite(camera.R) ||
        !allFinite(camera.T) || !(camera.K[0] > 0) || !(camera.K[4] > 0)) {
        throw CalibrationError(
            "camera model: the camera's numbers must be finite with positive focal lengths");
    }
    if (!(std::isfinite(radiusM) && radiusM > 0)) {
        throw CalibrationError(
            "camera model: the lamp's distance must be a positive number of "
            "metres");
    }
    const double sx = static_cast<double>(width) / camera.width;
    const double sy = static_cast<double>(height) / camera.height;
    const double aspectRatio = sx / sy;  // the stream's aspect over the calibration's
    if (std::abs(aspectRatio - 1.0) > kAspectTolerance) {
        char percent[32];
        std::snprintf(percent, sizeof percent, "%.1f%%", 100.0 * std::abs(aspectRatio - 1.0));
        throw CalibrationError(
            "the stream's " + sizeText(width, height) + " is not the camera calibration's " +
            sizeText(camera.width, camera.height) + " scaled: the aspect ratios differ by " +
            percent + " (more than 1%: a crop)");
    }
    streamCamera_.width = width;
    streamCamera_.height = height;
    auto& K = streamCamera_.K;
    K[0] = camera.K[0] * sx;
    K[1] = camera.K[1] * sx;
    K[2] = (camera.K[2] + 0.5) * sx - 0.5;
    K[4] = camera.K[4] * sy;
    K[5] = (camera.K[5] + 0.5) * sy - 0.5;
    centre_ = camera.center();
    const std::array<double, 3>& s = sphere.centre();
    fromSphere_ = {centre_.x - s[0], centre_.y - s[1], centre_.z - s[2]};
    clearance_ = proto::dot(fromSphere_, fromSphere_) - radiusM * radiusM;
    inside_ = clearance_ <= 0;
}

std::optional<LightDirection> CameraLampModel::direction(double u, double v) const {
    const proto::Vec3d d = proto::normalized(proto::pixelRayDirection(streamCamera_, {u, v}));
    // |fromSphere + t·d|² = r², d unit: t² + 2bt + clearance = 0.
    const double b = proto::dot(d, fromSphere_);
    const double discriminant = b * b - clearance_;
    if (!(discriminant >= 0)) {
        return std::nullopt;
    }
    const double root = std::sqrt(discriminant);
    // Outside: the near point, where the ray enters (only in front of the camera). Inside: the
    // one ahead; the other is behind the camera.
    const double t = inside_ ? -b + root : -b - root;
    if (!(t > 0)) {
        return std::nullopt;
    }
    const SphericalPosition spherical =
        sphere_.fromPosition({centre_.x + t * d.x, centre_.y + t * d.y, centre_.z + t * d.z});
    return LightDirection{spherical.azimuthDeg, spherical.elevationDeg};
}

}  // namespace vpe::firmware
