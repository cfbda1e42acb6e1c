// SPDX-License-Identifier: MIT
// CameraLampModel: the lamp's light direction from a calibrated camera. The camera's pose in the
// object frame (the bundle's camera, format 1.3) puts every image position on a ray; the lamp is
// held at a known distance from the object, so the ray meets the light's sphere where the lamp
// is, and the point's azimuth and elevation are the light's. The alternative to the board file's
// hand-measured table (LampCalibration).
#pragma once

#include <optional>

#include "vpe/firmware/light/light_sphere.h"
#include "vpe/firmware/tracking/lamp_calibration.h"
#include "vpe/proto/pinhole_camera.h"

namespace vpe::firmware {

class CameraLampModel {
public:
    // `camera`: object frame → camera at its calibrated resolution (proto's conventions). The
    // tracker's positions are in pixels of a `width` × `height` stream, the same field of view
    // scaled (a sensor mode binned or resized, not cropped), so the intrinsics are scaled per axis
    // with pixel centres at integers: c' = (c + ½)·s − ½, f' = f·s. `sphere`: the light's frame;
    // `radiusM`: the lamp's distance from its centre, metres. Throws CalibrationError, one line
    // without a file or key, when the two aspect ratios differ by more than 1% (a crop: the scaled
    // intrinsics would be wrong), for a size ≤ 0, non-finite numbers, focal lengths ≤ 0, or a
    // radius that is not a positive number.
    CameraLampModel(const proto::PinholeCamera& camera, int width, int height,
                    const LightSphere& sphere, double radiusM);

    // The light's direction for the lamp at (u, v) (stream pixels, undistorted by the camera's
    // model): where the pixel's ray from the camera's centre meets the sphere — the near point
    // for a camera outside it, the forward one for a camera inside. Nothing when the ray misses
    // the sphere (or, outside, meets it only behind the camera).
    std::optional<LightDirection> direction(double u, double v) const;

    // The camera with its intrinsics scaled to the stream.
    const proto::PinholeCamera& streamCamera() const { return streamCamera_; }
    const proto::PinholeCamera& calibratedCamera() const { return calibratedCamera_; }
    double radiusM() const { return radiusM_; }
    bool cameraInsideSphere() const { return inside_; }
    const LightSphere& sphere() const { return sphere_; }

private:
    proto::PinholeCamera calibratedCamera_;
    proto::PinholeCamera streamCamera_;
    LightSphere sphere_;
    double radiusM_ = 1.0;
    proto::Vec3d centre_;      // the camera's, object frame
    proto::Vec3d fromSphere_;  // centre_ − the sphere's centre
    double clearance_ = 0.0;   // |fromSphere_|² − r²: > 0 outside the sphere
    bool inside_ = false;
};

}  // namespace vpe::firmware
