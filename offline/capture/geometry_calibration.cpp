// SPDX-License-Identifier: MIT
// Applying a geometry calibration to a dome capture.
#include "vpe/capture/geometry_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpe::capture {

namespace {

// Elevation counts this many times azimuth (see lightIntensityAt).
constexpr double kElevationWeight = 3.0;

double lightDistanceSquared(const Vec3d& a, const Vec3d& b) {
    const double elevationA = std::asin(std::clamp(a.z, -1.0, 1.0));
    const double elevationB = std::asin(std::clamp(b.z, -1.0, 1.0));
    const double azimuth = std::remainder(std::atan2(a.y, a.x) - std::atan2(b.y, b.x), 2 * M_PI);
    const double along = azimuth * std::cos(0.5 * (elevationA + elevationB));
    const double up = kElevationWeight * (elevationA - elevationB);
    return along * along + up * up;
}

}  // namespace

double lightIntensityAt(const std::vector<LightIntensity>& table, const Vec3d& direction) {
    double nearest[2] = {std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::infinity()};
    double value[2] = {1.0, 1.0};
    for (const LightIntensity& entry : table) {
        const double d = lightDistanceSquared(entry.direction, direction);
        if (d < nearest[0]) {
            nearest[1] = nearest[0];
            value[1] = value[0];
            nearest[0] = d;
            value[0] = entry.intensity;
        } else if (d < nearest[1]) {
            nearest[1] = d;
            value[1] = entry.intensity;
        }
    }
    if (!std::isfinite(nearest[0])) {
        return 1.0;
    }
    // Within float rounding of an entry (the model file stores directions as floats): its own.
    constexpr double kSameLight = 1e-5;  // radians
    const double d0 = std::sqrt(nearest[0]);
    if (d0 < kSameLight || !std::isfinite(nearest[1])) {
        return value[0];
    }
    const double d1 = std::sqrt(nearest[1]);
    return (value[0] * d1 + value[1] * d0) / (d0 + d1);
}

bool acceptsGeometryCalibration(const Capture& capture) {
    return capture.lightKind == LightKind::kDirectional &&
           std::holds_alternative<OrthographicCamera>(capture.camera) && !capture.positionMap &&
           !capture.plane;
}

bool acceptsResponseCalibration(const Capture& capture) {
    return capture.encoding == ImageEncoding::kAuto || capture.encoding == ImageEncoding::kGamma;
}

Capture applyGeometryCalibration(const Capture& capture, const GeometryCalibration& calibration,
                                 int width, int height) {
    if (calibration.isIdentity()) {
        return capture;
    }
    Capture result = capture;
    if (!calibration.lightIntensities.empty()) {
        for (CaptureImage& image : result.images) {
            image.intensity *=
                lightIntensityAt(calibration.lightIntensities, proto::normalized(image.light));
        }
    }
    if (calibration.responseGamma > 0) {
        result.encoding = ImageEncoding::kGamma;
        result.gamma = calibration.responseGamma;
    }
    if (calibration.fieldOfViewDegrees == 0 && calibration.lightDistance == 0) {
        return result;
    }
    const double pixelSize = 2.0 / width;
    if (calibration.fieldOfViewDegrees > 0) {
        const double tangent = std::tan(calibration.fieldOfViewDegrees * M_PI / 360.0);
        PinholeCamera camera;
        camera.fx = camera.fy = (width / 2.0) / tangent;
        camera.cx = (width - 1) / 2.0;
        camera.cy = (height - 1) / 2.0;
        // Looking down −z with image y down: x_cam = x, y_cam = −y, z_cam = −z.
        camera.rotation = {1, 0, 0, 0, -1, 0, 0, 0, -1};
        camera.translation = {0, 0, 1.0 / tangent};
        result.camera = camera;
        result.plane = SurfacePlane{};
    } else {
        result.camera = OrthographicCamera{pixelSize};
    }
    if (calibration.lightDistance > 0) {
        result.lightKind = LightKind::kPoint;
        result.lightReferenceDistance = calibration.lightDistance;
        for (CaptureImage& image : result.images) {
            image.light = {image.light.x * calibration.lightDistance,
                           image.light.y * calibration.lightDistance,
                           image.light.z * calibration.lightDistance};
        }
    }
    return result;
}

Capture applyAcceptedCalibration(const Capture& capture, GeometryCalibration calibration, int width,
                                 int height) {
    if (!acceptsGeometryCalibration(capture)) {
        calibration.fieldOfViewDegrees = 0;
        calibration.lightDistance = 0;
        calibration.lightIntensities.clear();  // another rig's lights
    }
    if (!acceptsResponseCalibration(capture)) {
        calibration.responseGamma = 0;
    }
    return applyGeometryCalibration(capture, calibration, width, height);
}

}  // namespace vpe::capture
