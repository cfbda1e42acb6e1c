// SPDX-License-Identifier: MIT
// LampTracker: the camera input's decoding, free of hardware. Each frame → the brightest blob
// (BrightBlobTracker) → One Euro smoothing of its image position → the light direction, by the
// board's table (LampCalibration) or the calibrated camera (CameraLampModel) → InputEvent{kCamera,
// exposure time, AimLight}. LibcameraLamp feeds it camera frames; `vpe-player --replay` feeds it
// synthetic ones (SyntheticLampFrame).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/tracking/bright_blob_tracker.h"
#include "vpe/firmware/tracking/camera_lamp_model.h"
#include "vpe/firmware/tracking/lamp_calibration.h"
#include "vpe/firmware/tracking/luminance_frame.h"
#include "vpe/firmware/tracking/one_euro_filter.h"

namespace vpe::firmware {

struct LampTrackerSettings {
    // The image size the calibration's pixel positions refer to ([camera] size). Frames of
    // another size (a camera that adjusted the requested size) are rescaled to it.
    int width = 320;
    int height = 240;
    BlobTrackerConfig blob;
    OneEuroParameters filter;  // in pixels of width × height
    // How long a lost lamp keeps the light where it was before ReleaseLight, in (0, 3600]:
    // the time since the last frame that showed it, so it must exceed the frame interval or
    // ticks between frames would release a lamp in plain view.
    double holdSeconds = 0.5;
};

// Where the lamp's image position (pixels of LampTrackerSettings' size) points the light: the
// board file's hand-measured table, or the bundle's calibrated camera and the lamp's sphere.
using LampDirectionMap = std::variant<LampCalibration, CameraLampModel>;

// The refusal a position the camera model cannot map counts under (InputDevice::refusals).
inline constexpr const char* kLampRayMissesSphere = "camera.ray_misses_sphere";

class LampTracker {
public:
    // Throws std::invalid_argument for invalid settings.
    LampTracker(const LampTrackerSettings& settings, LampDirectionMap map);

    // A frame exposed at `timestampNs` (CLOCK_MONOTONIC): appends one AimLight when the lamp
    // is in it, or a ReleaseLight when it has now been missing for the hold time. Throws
    // std::invalid_argument for a malformed view.
    void onFrame(const LuminanceView& frame, std::int64_t timestampNs,
                 std::vector<InputEvent>& events);

    // The hold time may run out with no frame arriving (camera stalled or unplugged): appends
    // the ReleaseLight then.
    void tick(std::int64_t nowNs, std::vector<InputEvent>& events);

    // True between the first AimLight after a (re)acquisition and the ReleaseLight.
    bool steering() const { return steering_; }
    // The newest frame's blob (nullopt when the lamp was not in it): for calibration and logs.
    const std::optional<Blob>& lastBlob() const { return lastBlob_; }
    const LampTrackerSettings& settings() const { return settings_; }

    // A new map from the next frame on (a reloaded bundle's camera); the smoothing carries on.
    void setDirectionMap(LampDirectionMap map) { map_ = std::move(map); }
    const LampDirectionMap& directionMap() const { return map_; }
    // Frames whose lamp the map could not place (the camera model's ray missed the sphere):
    // each counted as a frame without the lamp, so the hold and release run as for a lost lamp.
    std::uint64_t unmappedFrames() const { return unmappedFrames_; }
    // {kLampRayMissesSphere: unmappedFrames()} when there were any, for the player's report.
    std::map<std::string, std::uint64_t> refusals() const;

private:
    void releaseIfHoldExpired(std::int64_t nowNs, std::vector<InputEvent>& events);

    LampTrackerSettings settings_;
    LampDirectionMap map_;
    BrightBlobTracker blobs_;
    OneEuroFilter filterU_;
    OneEuroFilter filterV_;
    std::int64_t holdNs_ = 0;
    bool steering_ = false;
    std::int64_t lastSeenNs_ = 0;
    std::optional<Blob> lastBlob_;
    std::uint64_t unmappedFrames_ = 0;
};

}  // namespace vpe::firmware
