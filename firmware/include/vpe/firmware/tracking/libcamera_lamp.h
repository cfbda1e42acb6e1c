// SPDX-License-Identifier: MIT
// LibcameraLamp: the camera-tracked lamp as an InputDevice (libcamera 0.0.3). The camera runs
// at a fixed exposure and gain; libcamera's thread hands completed requests over through a
// mutex-protected queue and an eventfd, and the player's loop runs LampTracker on the newest
// frame (older ones are dropped: latency over completeness).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/tracking/camera_config.h"
#include "vpe/firmware/tracking/lamp_tracker.h"

namespace vpe::firmware {

// The camera cannot be used: none present, the requested id absent, busy, or refusing the
// configuration. One line starting "camera: " or "camera <id>: ", e.g. "camera: no camera found
// (libcamera lists none)".
class CameraUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class LibcameraLamp final : public InputDevice {
public:
    // Starts a libcamera CameraManager, acquires and configures the camera (luminance-first
    // format: R8, YUV420, NV12, NV21 or YVU420; config.tracking's size), maps its buffers and
    // starts streaming; positions become directions through `map` (lampDirectionMapOf). Throws
    // CameraUnavailable. libcamera allows one CameraManager per process, so at most one
    // LibcameraLamp may exist at a time.
    LibcameraLamp(const CameraConfig& config, LampDirectionMap map);
    // The same with config.calibration's table; also throws CalibrationError when the table
    // does not determine a map.
    explicit LibcameraLamp(const CameraConfig& config);
    // Stops streaming and releases the camera; returns once libcamera's thread is done with
    // this object.
    ~LibcameraLamp() override;

    std::string description() const override;
    std::vector<int> pollDescriptors() const override;  // {the eventfd}
    void onReadable(int fd, std::int64_t nowNs, std::vector<InputEvent>& events) override;
    void onTick(std::int64_t nowNs, std::vector<InputEvent>& events) override;

    // Lamp positions the map could not place, per reason (kLampRayMissesSphere).
    std::map<std::string, std::uint64_t> refusals() const override { return tracker_.refusals(); }

    const LampTracker& tracker() const { return tracker_; }
    // A reloaded bundle's camera: the next frame on.
    void setDirectionMap(LampDirectionMap map) { tracker_.setDirectionMap(std::move(map)); }

private:
    class Session;  // the libcamera objects, kept out of this header

    LampTracker tracker_;
    std::unique_ptr<Session> session_;
};

}  // namespace vpe::firmware
