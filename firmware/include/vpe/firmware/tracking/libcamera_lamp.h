// SPDX-License-Identifier: MIT
// LibcameraLamp: the camera-tracked lamp as an InputDevice (libcamera 0.0.3). The camera runs
// at a fixed exposure and gain (LibcameraStream, shared with the scan); its eventfd joins the
// player's loop, which runs LampTracker on the newest frame (older ones are dropped: latency
// over completeness).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "vpe/firmware/input/input_device.h"
#include "vpe/firmware/tracking/camera_config.h"
#include "vpe/firmware/tracking/lamp_tracker.h"
#include "vpe/firmware/tracking/libcamera_stream.h"

namespace vpe::firmware {

class LibcameraLamp final : public InputDevice {
public:
    // Opens the camera as a viewfinder stream of config.tracking's size at the fixed exposure
    // and gain (LibcameraStream); positions become directions through `map`
    // (lampDirectionMapOf). Throws CameraUnavailable. libcamera allows one CameraManager per
    // process, so at most one LibcameraLamp (or other LibcameraStream) may exist at a time.
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
    LampTracker tracker_;
    LibcameraStream stream_;
};

}  // namespace vpe::firmware
