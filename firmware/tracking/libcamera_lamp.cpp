// SPDX-License-Identifier: MIT
// LibcameraLamp: the lamp's viewfinder stream (LibcameraStream) feeding LampTracker on the
// player's thread.
#include "vpe/firmware/tracking/libcamera_lamp.h"

#include <utility>

namespace vpe::firmware {

namespace {

CameraStreamSettings lampStreamOf(const CameraConfig& config) {
    CameraStreamSettings settings;
    settings.id = config.id;
    settings.width = config.tracking.width;
    settings.height = config.tracking.height;
    settings.role = CameraStreamRole::kViewfinder;
    settings.exposureUs = config.exposureUs;
    settings.analogueGain = config.analogueGain;
    return settings;
}

}  // namespace

LibcameraLamp::LibcameraLamp(const CameraConfig& config, LampDirectionMap map)
    : tracker_(config.tracking, std::move(map)), stream_(lampStreamOf(config)) {}

LibcameraLamp::LibcameraLamp(const CameraConfig& config)
    : LibcameraLamp(config, LampCalibration::fit(config.calibration)) {}

LibcameraLamp::~LibcameraLamp() = default;

std::string LibcameraLamp::description() const {
    return stream_.description();
}

std::vector<int> LibcameraLamp::pollDescriptors() const {
    return {stream_.eventFd()};
}

void LibcameraLamp::onReadable(int fd, std::int64_t /*nowNs*/, std::vector<InputEvent>& events) {
    if (fd != stream_.eventFd()) {
        return;
    }
    stream_.drain(
        [this, &events](const CameraFrameView& frame) {
            tracker_.onFrame(frame.luminance, frame.timestampNs, events);
        },
        /*newestOnly=*/true);
}

void LibcameraLamp::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    tracker_.tick(nowNs, events);
}

}  // namespace vpe::firmware
