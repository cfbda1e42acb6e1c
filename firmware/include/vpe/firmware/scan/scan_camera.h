// SPDX-License-Identifier: MIT
// ScanCamera: what photographs a scan's patterns — the board's libcamera camera
// (LibcameraScanCamera) or the projector–camera simulator (SimulatedScanCamera) — behind one
// interface, so that the scan's loop, its checks and its folder are the same for both.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/firmware/scan/camera_image.h"

namespace vpe::firmware {

// The scan could not be completed (a capture that keeps failing its check, a camera that stops
// delivering frames): vpe-player exits with status 1, one line, and writes nothing.
class ScanError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ScanCameraInfo {
    std::string source;       // the manifest's camera.source: "libcamera:<id>", "simulated:<file>"
    std::string description;  // for the log and the report
    int width = 0, height = 0;
    int bits = 8;
    double exposureUs = 0;  // 0: not known (a simulation's exposure is relative)
    double analogueGain = 1;
};

class ScanCamera {
public:
    virtual ~ScanCamera() = default;

    virtual const ScanCameraInfo& info() const = 0;

    // True when the camera must be told what the display shows (a simulation renders it).
    virtual bool needsShownImage() const { return false; }
    // The display shows `rgba` (RGBA8, width × height, rows from the top) since `shownNs`
    // (CLOCK_MONOTONIC).
    virtual void patternShown(const std::vector<std::uint8_t>& /*rgba*/, int /*width*/,
                              int /*height*/, std::int64_t /*shownNs*/) {}

    // One image whose exposure starts at or after `notBeforeNs` (CLOCK_MONOTONIC). Throws
    // ScanError when the camera delivers none.
    virtual CameraImage capture(std::int64_t notBeforeNs) = 0;
};

// CLOCK_MONOTONIC now, nanoseconds (the clock of libcamera's timestamps and of page flips).
std::int64_t scanClockNs();
// Sleeps until CLOCK_MONOTONIC reaches `ns` (returns at once when it has).
void sleepUntilNs(std::int64_t ns);

}  // namespace vpe::firmware
