// SPDX-License-Identifier: MIT
// LibcameraScanCamera: the first frame exposed after the pattern is up, copied out of the
// camera's buffer.
#include "vpe/firmware/scan/libcamera_scan_camera.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>

#include <poll.h>

namespace vpe::firmware {

namespace {

constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kBaseTimeoutNs = 1000 * kNsPerMs;

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
    timeoutNs_ = kBaseTimeoutNs + 4 * static_cast<std::int64_t>(settings.exposureUs) * 1000;
}

CameraImage LibcameraScanCamera::capture(std::int64_t notBeforeNs) {
    const std::int64_t deadlineNs = std::max(notBeforeNs, scanClockNs()) + timeoutNs_;
    std::optional<CameraImage> image;
    while (!image) {
        const std::int64_t leftNs = deadlineNs - scanClockNs();
        if (leftNs <= 0) {
            throw ScanError("camera " + stream_.cameraId() + ": no frame within " +
                            std::to_string(timeoutNs_ / kNsPerMs) +
                            " ms of the time asked for (has it stopped streaming?)");
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
        // is copied (the buffer is the camera's again after the call).
        stream_.drain(
            [&image, notBeforeNs](const CameraFrameView& frame) {
                if (image || frame.timestampNs < notBeforeNs) {
                    return;
                }
                const LuminanceView& view = frame.luminance;
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
                image = std::move(copy);
            },
            /*newestOnly=*/false);
    }
    return *image;
}

}  // namespace vpe::firmware
