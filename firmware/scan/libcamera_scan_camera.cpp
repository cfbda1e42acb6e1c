// SPDX-License-Identifier: MIT
// LibcameraScanCamera: the first frame exposed after the pattern is up (and at the exposure
// asked for), copied out of the camera's buffer: its Y plane, or R, G, B from Y'CbCr.
#include "vpe/firmware/scan/libcamera_scan_camera.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include <poll.h>

#include "vpe/proto/luminance.h"

namespace vpe::firmware {

namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kBaseTimeoutNs = 1000 * kNsPerMs;
// A frame is at the exposure asked for when its metadata says so within this much (sensors
// expose whole lines: tens of µs).
constexpr double kExposureTolerance = 0.02;
constexpr std::int32_t kExposureToleranceUs = 50;
// Without ExposureTime metadata: frames to let pass after a change (libcamera pipelines apply
// a control a few frames after the request that carried it).
constexpr int kExposureSettleFrames = 5;

CameraImage luminanceOf(const LuminanceView& view) {
    CameraImage copy;
    copy.width = view.width;
    copy.height = view.height;
    copy.maxValue = 255;
    copy.samples.resize(copy.pixelCount());
    for (int y = 0; y < view.height; ++y) {
        const std::uint8_t* row = view.row(y);
        std::copy(row, row + view.width,
                  copy.samples.begin() + static_cast<std::ptrdiff_t>(y) * view.width);
    }
    return copy;
}

// Y'CbCr → R'G'B' with the stream's matrix and range; each chroma sample serves 2 × 2 pixels.
CameraImage colourOf(const LuminanceView& luma, const ChromaView& chroma) {
    double kr = 0.299, kb = 0.114;  // Rec. 601
    if (chroma.encoding == ChromaView::Encoding::kRec709) {
        kr = proto::kLuminance709[0];
        kb = proto::kLuminance709[2];
    } else if (chroma.encoding == ChromaView::Encoding::kRec2020) {
        kr = 0.2627;
        kb = 0.0593;
    }
    const double kg = 1.0 - kr - kb;
    const double lumaScale = chroma.fullRange ? 1.0 : 255.0 / 219.0;
    const double lumaOffset = chroma.fullRange ? 0.0 : 16.0;
    const double chromaScale = chroma.fullRange ? 1.0 : 255.0 / 224.0;
    CameraImage copy;
    copy.width = luma.width;
    copy.height = luma.height;
    copy.channels = 3;
    copy.maxValue = 255;
    copy.samples.resize(copy.sampleCount());
    const auto code = [](double value) {
        return static_cast<std::uint16_t>(std::lround(std::clamp(value, 0.0, 255.0)));
    };
    for (int y = 0; y < luma.height; ++y) {
        const std::uint8_t* row = luma.row(y);
        std::uint16_t* out = copy.samples.data() + static_cast<std::ptrdiff_t>(y) * luma.width * 3;
        for (int x = 0; x < luma.width; ++x) {
            const double yy = (row[x] - lumaOffset) * lumaScale;
            const double cb = (chroma.cbAt(x / 2, y / 2) - 128.0) * chromaScale;
            const double cr = (chroma.crAt(x / 2, y / 2) - 128.0) * chromaScale;
            const double r = yy + 2.0 * (1.0 - kr) * cr;
            const double b = yy + 2.0 * (1.0 - kb) * cb;
            const double g = (yy - kr * r - kb * b) / kg;
            out[3 * x] = code(r);
            out[3 * x + 1] = code(g);
            out[3 * x + 2] = code(b);
        }
    }
    return copy;
}

}  // namespace

LibcameraScanCamera::LibcameraScanCamera(const CameraStreamSettings& settings) : stream_(settings) {
    info_.source = "libcamera:" + stream_.cameraId();
    info_.description = stream_.description();
    info_.width = stream_.width();
    info_.height = stream_.height();
    info_.bits = 8;
    // Without an ExposureTime control the camera exposes automatically: the exposure is then
    // not known (the description says so).
    info_.exposureUs = stream_.exposureFixed() ? settings.exposureUs : 0;
    info_.analogueGain = settings.analogueGain;
    baseExposureUs_ = settings.exposureUs;
    exposureUs_ = settings.exposureUs;
    framesSinceExposure_ = kExposureSettleFrames;  // the stream started at it
    timeoutNs_ = kBaseTimeoutNs + 4 * static_cast<std::int64_t>(settings.exposureUs) * 1000;
}

ColourCapture LibcameraScanCamera::colourCapture() const {
    ColourCapture colour;
    colour.response = proto::CameraResponseKind::kUnknown;
    colour.bits = 8;
    if (!stream_.colourAbsence().empty()) {
        colour.unavailable = "camera " + stream_.cameraId() + " " + stream_.colourAbsence();
    } else if (!stream_.exposureFixed()) {
        colour.unavailable = "camera " + stream_.cameraId() +
                             " has no ExposureTime control: the bracket that measures its "
                             "response needs a fixed exposure it can scale";
    }
    colour.description = "the ISP's 8-bit Y'CbCr as R'G'B' (response unknown: a bracketed ramp)";
    colour.note =
        "the ISP's 8-bit output, its response measured by a bracketed ramp; raw Bayer "
        "frames (a linear response) are not taken by this build";
    return colour;
}

CameraImage LibcameraScanCamera::capture(std::int64_t notBeforeNs, const CaptureRequest& request) {
    if (request.colour && !stream_.colourAbsence().empty()) {
        throw ScanError("camera " + stream_.cameraId() + ": " + stream_.colourAbsence());
    }
    const auto wanted =
        static_cast<std::int32_t>(std::lround(baseExposureUs_ * request.exposureScale));
    if (wanted != exposureUs_) {
        stream_.setExposureUs(wanted);
        exposureUs_ = wanted;
        framesSinceExposure_ = 0;
    }
    const std::int32_t tolerance = std::max(
        kExposureToleranceUs, static_cast<std::int32_t>(std::lround(kExposureTolerance * wanted)));
    const bool checkExposure = stream_.exposureFixed() && wanted != baseExposureUs_;
    const std::int64_t deadlineNs = std::max(notBeforeNs, scanClockNs()) + timeoutNs_;
    std::optional<CameraImage> image;
    std::optional<std::int32_t> lastExposure;
    while (!image) {
        const std::int64_t leftNs = deadlineNs - scanClockNs();
        if (leftNs <= 0) {
            std::string problem = "camera " + stream_.cameraId() + ": no frame within " +
                                  std::to_string(timeoutNs_ / kNsPerMs) +
                                  " ms of the time asked for";
            if (checkExposure && lastExposure) {
                problem += " at an exposure of " + std::to_string(wanted) + " us (frames say " +
                           std::to_string(*lastExposure) + " us)";
            } else {
                problem += " (has it stopped streaming?)";
            }
            throw ScanError(problem);
        }
        pollfd ready{stream_.eventFd(), POLLIN, 0};
        const int result = ::poll(
            &ready, 1, static_cast<int>(std::min<std::int64_t>(leftNs / kNsPerMs + 1, 1000)));
        if (result < 0 && errno != EINTR) {
            throw ScanError("camera " + stream_.cameraId() + ": poll (" + std::strerror(errno) +
                            ")");
        }
        if (result <= 0) {
            continue;
        }
        // Every completed frame is handed back to the camera; the first one exposed late enough
        // (and long enough) is copied (the buffer is the camera's again after the call).
        stream_.drain(
            [&](const CameraFrameView& frame) {
                ++framesSinceExposure_;
                if (image || frame.timestampNs < notBeforeNs) {
                    return;
                }
                if (checkExposure || framesSinceExposure_ <= kExposureSettleFrames) {
                    if (frame.exposureUs) {
                        lastExposure = frame.exposureUs;
                        if (std::abs(*frame.exposureUs - wanted) > tolerance) {
                            return;
                        }
                    } else if (framesSinceExposure_ <= kExposureSettleFrames) {
                        return;
                    }
                }
                if (request.colour && frame.chroma) {
                    image = colourOf(frame.luminance, *frame.chroma);
                } else {
                    image = luminanceOf(frame.luminance);
                }
            },
            /*newestOnly=*/false);
    }
    return *image;
}

}  // namespace vpe::firmware
