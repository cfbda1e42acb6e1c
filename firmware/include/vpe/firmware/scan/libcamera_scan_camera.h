// SPDX-License-Identifier: MIT
// LibcameraScanCamera: the board's camera (the lamp's, [camera] id) streaming its still
// capture at the scan's size, fixed exposure, gain and white balance (LibcameraStream). A
// capture is the first frame whose exposure starts at or after the time asked for: the camera
// keeps streaming, and frames exposed before the pattern was up (plus the projector's latency)
// are dropped by their sensor timestamps. The scan's captures are the Y plane; the radiometric
// capture's are the ISP's Y'CbCr 4:2:0 converted to R'G'B' (8 bits, the ISP's curve: response
// unknown, so the ramp is bracketed through ExposureTime). Raw Bayer frames (a linear response)
// are not taken: that needs a raw stream beside the processed one, untried without a camera.
#pragma once

#include <cstdint>

#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/firmware/tracking/libcamera_stream.h"

namespace vpe::firmware {

class LibcameraScanCamera final : public ScanCamera {
public:
    // Throws CameraUnavailable (one line, "camera: no camera found (libcamera lists none)").
    // `settings.colour` asks for a stream with chroma (the radiometric capture).
    explicit LibcameraScanCamera(const CameraStreamSettings& settings);

    const ScanCameraInfo& info() const override { return info_; }
    // Unavailable without chroma (colour not asked for, an R8 stream) or without an
    // ExposureTime control (the bracket scales the exposure).
    ColourCapture colourCapture() const override;
    // The Y plane, 8 bits, or R, G, B from Y'CbCr (chroma upsampled by repetition). A request
    // with another exposure sets ExposureTime and takes the first frame exposed at it (its
    // ExposureTime metadata within 2 % or 50 µs; without that metadata, the fifth frame after
    // the change). Throws ScanError when no such frame arrives within a second plus four
    // exposures.
    CameraImage capture(std::int64_t notBeforeNs, const CaptureRequest& request) override;

private:
    LibcameraStream stream_;
    ScanCameraInfo info_;
    std::int32_t baseExposureUs_ = 0;
    std::int32_t exposureUs_ = 0;  // asked of the camera now
    int framesSinceExposure_ = 0;  // frames seen since it was asked
    std::int64_t timeoutNs_ = 0;
};

}  // namespace vpe::firmware
