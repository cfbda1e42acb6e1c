// SPDX-License-Identifier: MIT
// LibcameraStream: one libcamera 0.0.3 camera streaming its luminance plane at a fixed exposure
// and gain — the session the tracked lamp (LibcameraLamp) and the scan (vpe-player --scan)
// share. libcamera's thread hands completed requests over through a mutex-protected list and
// an eventfd; the owner's thread reads the frames and queues the requests again. The libcamera
// objects stay out of this header (and out of every room but tracking/).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "vpe/firmware/tracking/luminance_frame.h"

namespace vpe::firmware {

// The camera cannot be used: none present, the requested id absent, busy, or refusing the
// configuration. One line starting "camera: " or "camera <id>: ", e.g. "camera: no camera found
// (libcamera lists none)".
class CameraUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Which of libcamera's stream roles to configure: the viewfinder (small, fast: the lamp) or the
// still capture (the sensor's full processing: the scan).
enum class CameraStreamRole : std::uint8_t { kViewfinder, kStillCapture };

struct CameraStreamSettings {
    std::string id = "auto";  // "auto": libcamera's first camera
    int width = 320, height = 240;
    CameraStreamRole role = CameraStreamRole::kViewfinder;
    // Fixed, with auto exposure off (controls the camera does not list are left alone).
    int exposureUs = 2000;
    double analogueGain = 1.0;
    // Auto white balance off as well, and the red and blue gains fixed when given: the ISP's
    // luminance is computed after the colour gains, so a white balance that adapts between two
    // frames would change Y too.
    bool fixedWhiteBalance = false;
    std::optional<std::array<double, 2>> colourGains;
    // Frame durations allowed (µs; FrameDurationLimits), when set: room for a long exposure,
    // which the pipeline would otherwise cap at its default longest frame.
    std::optional<std::array<std::int64_t, 2>> frameDurationUs;
    // At least this many frame buffers (0: the pipeline's count; a still stream may have one).
    unsigned minBuffers = 0;
};

// A completed frame, lent for the duration of a callback.
struct CameraFrameView {
    LuminanceView luminance;  // the first plane (R8, or Y of YUV420/NV12/NV21/YVU420)
    // The start of the exposure of the first row (SensorTimestamp; else the buffer's
    // timestamp), CLOCK_MONOTONIC nanoseconds.
    std::int64_t timestampNs = 0;
};

class LibcameraStream {
public:
    // In the order of libcamera's `cam` tool: CameraManager start, pick and acquire the camera,
    // generate/validate/configure (a luminance-first format: R8, YUV420, NV12, NV21 or YVU420),
    // allocate and map the buffers, create the requests, start with the fixed controls, queue.
    // Throws CameraUnavailable, having undone whatever was done. libcamera allows one
    // CameraManager per process, so at most one LibcameraStream may exist at a time.
    explicit LibcameraStream(const CameraStreamSettings& settings);
    // Stops streaming and releases the camera; returns once libcamera's thread is done with
    // this object.
    ~LibcameraStream();
    LibcameraStream(const LibcameraStream&) = delete;
    LibcameraStream& operator=(const LibcameraStream&) = delete;

    // Readable when frames have completed since the last drain().
    int eventFd() const;
    // "camera (imx219 1640x1232-YUV420, exposure 20000 us, gain 1)".
    const std::string& description() const;
    const std::string& cameraId() const;
    // The stream as configured (the camera may have adjusted the requested size).
    int width() const;
    int height() const;
    // True when the camera lists ExposureTime (the exposure really is fixed).
    bool exposureFixed() const;

    // Takes the requests completed since the last call, hands their good frames to `onFrame`
    // in capture order (only the newest when `newestOnly`: latency over completeness), then
    // queues them all again. A frame's view is valid only during its call.
    void drain(const std::function<void(const CameraFrameView&)>& onFrame, bool newestOnly);

private:
    class Session;  // the libcamera objects

    std::unique_ptr<Session> session_;
};

}  // namespace vpe::firmware
