// SPDX-License-Identifier: MIT
// The board file's [camera] section: which camera tracks the lamp, its fixed exposure, the
// blob's limits, the smoothing, the hold time and the calibration (firmware/tracking/README.md).
#pragma once

#include <string>
#include <vector>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

#include "vpe/firmware/tracking/lamp_calibration.h"
#include "vpe/firmware/tracking/lamp_tracker.h"

namespace vpe::firmware {

struct CameraConfig {
    bool enabled = false;
    std::string id = "auto";  // "auto": libcamera's first camera; else a libcamera camera id
    // Fixed exposure and gain (auto exposure would brighten the room until the lamp is lost).
    int exposureUs = 2000;
    double analogueGain = 1.0;
    // size (width, height), threshold, relative_threshold, min_area, max_area, hold_s, filter.
    LampTrackerSettings tracking;
    // [u, v, azimuth_deg, elevation_deg], u and v in pixels of `size`. Validated by fitting
    // (LampCalibration::fit) when present; required (≥ 3 points) when enabled.
    std::vector<CalibrationPoint> calibration;
};

// Reads the [camera] table strictly: unknown keys, wrong types and values out of range are
// refused with BoardConfigError, one line naming "source:camera.key" (camera.calibration[2] for
// one point).
CameraConfig parseCameraConfig(const toml::table& camera, const std::string& source);

}  // namespace vpe::firmware
