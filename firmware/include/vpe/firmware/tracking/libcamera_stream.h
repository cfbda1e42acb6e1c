// SPDX-License-Identifier: MIT
// LibcameraStream: one libcamera 0.0.3 camera streaming its luminance plane at a fixed exposure
// and gain — the session the tracked lamp (LibcameraLamp) and the scan (vpe-player --scan)
// share; for the scan's radiometric capture also the colour planes of a YUV 4:2:0 stream and an
// exposure that can be changed while streaming. libcamera's thread hands completed requests over
// through a mutex-protected list and an eventfd; the owner's thread reads the frames and queues the
// requests again. The libcamera objects stay out of this header (and out of every room but
// tracking/).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
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
    // Colour wanted too: a YUV 4:2:0 format (luminance first, then the chroma planes) is
    // preferred to R8, and frames carry their chroma (CameraFrameView::chroma).
    bool colour = false;
};

// The chroma of a YUV 4:2:0 frame, lent with it: Cb and Cr at half the luminance's width and
// height (rounded up), sample (x, y) of each at byte y·stride + x·step of its span (step 1 for
// planar YUV420/YVU420, 2 for interleaved NV12/NV21), and how Y'CbCr encodes R'G'B' (the
// stream's colour space; Rec. 601 full range, as JPEG, when the camera does not say).
struct ChromaView {
    enum class Encoding : std::uint8_t { kRec601, kRec709, kRec2020 };

    int width = 0, height = 0;
    int stride = 0;
    int step = 1;
    std::span<const std::uint8_t> cb, cr;
    Encoding encoding = Encoding::kRec601;
    bool fullRange = true;

    std::uint8_t cbAt(int x, int y) const {
        return cb[static_cast<std::size_t>(y) * static_cast<std::size_t>(stride) +
                  static_cast<std::size_t>(x) * static_cast<std::size_t>(step)];
    }
    std::uint8_t crAt(int x, int y) const {
        return cr[static_cast<std::size_t>(y) * static_cast<std::size_t>(stride) +
                  static_cast<std::size_t>(x) * static_cast<std::size_t>(step)];
    }
};

// A completed frame, lent for the duration of a callback.
struct CameraFrameView {
    LuminanceView luminance;  // the first plane (R8, or Y of YUV420/NV12/NV21/YVU420)
    // The start of the exposure of the first row (SensorTimestamp; else the buffer's
    // timestamp), CLOCK_MONOTONIC nanoseconds.
    std::int64_t timestampNs = 0;
    // With CameraStreamSettings::colour and a YUV 4:2:0 stream whose buffers hold the chroma.
    std::optional<ChromaView> chroma;
    // The frame's exposure as the camera reports it (ExposureTime metadata), when it does.
    std::optional<std::int32_t> exposureUs;
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
    // Why frames carry no chroma ("" when they do: colour was asked for and the stream is YUV
    // 4:2:0 with buffers that hold it), one phrase after the camera: "streams R8, which has no
    // colour".
    const std::string& colourAbsence() const;
    // Requests queued from now on ask for this exposure (ExposureTime; only when the camera
    // lists it). The pipeline applies it some frames later: CameraFrameView::exposureUs tells.
    void setExposureUs(std::int32_t exposureUs);

    // Takes the requests completed since the last call, hands their good frames to `onFrame`
    // in capture order (only the newest when `newestOnly`: latency over completeness), then
    // queues them all again. A frame's view is valid only during its call.
    void drain(const std::function<void(const CameraFrameView&)>& onFrame, bool newestOnly);

private:
    class Session;  // the libcamera objects

    std::unique_ptr<Session> session_;
};

}  // namespace vpe::firmware
