// SPDX-License-Identifier: MIT
// LampTracker: the camera input's decoding, free of hardware. Each frame → the brightest blob
// (BrightBlobTracker) → One Euro smoothing of its image position → the calibration's light
// direction → InputEvent{kCamera, exposure time, AimLight}. LibcameraLamp feeds it camera
// frames; `vpe-player --replay` feeds it synthetic ones (SyntheticLampFrame).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "vpe/firmware/input/input_event.h"
#include "vpe/firmware/tracking/bright_blob_tracker.h"
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

class LampTracker {
public:
    // Throws std::invalid_argument for invalid settings.
    LampTracker(const LampTrackerSettings& settings, LampCalibration calibration);

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

private:
    void releaseIfHoldExpired(std::int64_t nowNs, std::vector<InputEvent>& events);

    LampTrackerSettings settings_;
    LampCalibration calibration_;
    BrightBlobTracker blobs_;
    OneEuroFilter filterU_;
    OneEuroFilter filterV_;
    std::int64_t holdNs_ = 0;
    bool steering_ = false;
    std::int64_t lastSeenNs_ = 0;
    std::optional<Blob> lastBlob_;
};

}  // namespace vpe::firmware
