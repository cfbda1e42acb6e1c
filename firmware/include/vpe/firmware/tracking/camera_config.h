// SPDX-License-Identifier: MIT
// The board file's [camera] section: which camera tracks the lamp, its fixed exposure, the
// blob's limits, the smoothing, the hold time and the calibration — the hand-measured table, or
// the bundle's camera and the lamp's distance (firmware/tracking/README.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/light/light_sphere.h"
#include "vpe/firmware/tracking/lamp_calibration.h"
#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/proto/pinhole_camera.h"

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
    // (LampCalibration::fit) when present. Absent: the bundle's camera maps the lamp instead
    // (lampDirectionMapOf); one of the two is required when enabled.
    std::vector<CalibrationPoint> calibration;
    // The lamp's distance from the light sphere's centre, metres, for the camera model; unset:
    // [light] initial_distance, else 2 × the object's bounding radius (as the light rig).
    std::optional<double> lampDistanceM;
};

// Reads the [camera] table strictly: unknown keys, wrong types and values out of range are
// refused with BoardConfigError, one line naming "source:camera.key" (camera.calibration[2] for
// one point).
CameraConfig parseCameraConfig(const toml::table& camera, const std::string& source);

// The map the tracker turns the lamp's image position into a light direction with: the board's
// table when `config` has one (the bundle's camera is then unused), else the camera model of
// `bundleCamera` (the bundle's, format 1.3) at config.tracking's size on `sphere` (the
// bundle's), the lamp at lampDistanceM, else `light`'s initial distance, else 2 × the object's
// radius. Throws BoardConfigError, one line: "source:camera.calibration: absent, and the bundle
// carries no camera (…)" when neither is there, "source:camera.size: …" when the stream's aspect
// ratio is not the camera's.
LampDirectionMap lampDirectionMapOf(const CameraConfig& config,
                                    const std::optional<proto::PinholeCamera>& bundleCamera,
                                    const LightSphere& sphere, const LightConfig& light,
                                    const std::string& source);

// One phrase for logs and --check: "the table (6 points, quadratic)", "the bundle's camera
// (1640x1232 scaled to 320x240; lamp sphere 0.5 m, the camera outside it)".
std::string describeLampDirectionMap(const LampDirectionMap& map);

}  // namespace vpe::firmware
