// SPDX-License-Identifier: MIT
// LibcameraScanCamera: the board's camera (the lamp's, [camera] id) streaming its still
// capture at the scan's size, fixed exposure, gain and white balance (LibcameraStream). A
// capture is the first frame whose exposure starts at or after the time asked for: the camera
// keeps streaming, and frames exposed before the pattern was up (plus the projector's latency)
// are dropped by their sensor timestamps.
#pragma once

#include <cstdint>

#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/firmware/tracking/libcamera_stream.h"

namespace vpe::firmware {

class LibcameraScanCamera final : public ScanCamera {
public:
    // Throws CameraUnavailable (one line, "camera: no camera found (libcamera lists none)").
    explicit LibcameraScanCamera(const CameraStreamSettings& settings);

    const ScanCameraInfo& info() const override { return info_; }
    // The Y plane, 8 bits. Throws ScanError when no such frame arrives within a second plus
    // four exposures.
    CameraImage capture(std::int64_t notBeforeNs) override;

private:
    LibcameraStream stream_;
    ScanCameraInfo info_;
    std::int64_t timeoutNs_ = 0;
};

}  // namespace vpe::firmware
