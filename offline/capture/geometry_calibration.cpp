// SPDX-License-Identifier: MIT
// Applying a geometry calibration to a dome capture.
#include "vpe/capture/geometry_calibration.h"

#include <cmath>

namespace vpe {

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
    }
    if (!acceptsResponseCalibration(capture)) {
        calibration.responseGamma = 0;
    }
    return applyGeometryCalibration(capture, calibration, width, height);
}

}  // namespace vpe
