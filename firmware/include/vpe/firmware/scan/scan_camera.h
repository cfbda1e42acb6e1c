// SPDX-License-Identifier: MIT
// ScanCamera: what photographs a scan's patterns and the radiometric capture's flat fields —
// the board's libcamera camera (LibcameraScanCamera) or the projector–camera simulator
// (SimulatedScanCamera) — behind one interface, so that the loop, its checks and the folder
// are the same for both.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/firmware/scan/camera_image.h"
#include "vpe/proto/radiometry_capture.h"

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

// How one capture is taken: the structured-light patterns in luminance at the fixed exposure
// (the default), the radiometric capture's flat fields in colour, its bracketed ramp at a
// fraction of the exposure.
struct CaptureRequest {
    bool colour = false;       // three channels (R, G, B) instead of one
    double exposureScale = 1;  // × the fixed exposure (proto::FlatField::exposureScale)
};

// Whether and how the camera photographs in colour for the radiometric capture
// (proto/RADIOMETRY.md's camera: response and bits; a response that is not known to be linear
// is measured with a bracketed ramp, so the exposure must then be scalable and the codes 8-bit).
struct ColourCapture {
    std::string unavailable;  // why the camera cannot, one line; "" when it can
    proto::CameraResponseKind response = proto::CameraResponseKind::kLinear;
    int bits = 8;
    std::string description;  // what it records, for the report
    std::string note;         // a line to log when the capture starts ("" for none)

    bool available() const { return unavailable.empty(); }
};

class ScanCamera {
public:
    virtual ~ScanCamera() = default;

    virtual const ScanCameraInfo& info() const = 0;
    virtual ColourCapture colourCapture() const = 0;

    // True when the camera must be told what the display shows (a simulation renders it).
    virtual bool needsShownImage() const { return false; }
    // The display shows `rgba` (RGBA8, width × height, rows from the top) since `shownNs`
    // (CLOCK_MONOTONIC).
    virtual void patternShown(const std::vector<std::uint8_t>& /*rgba*/, int /*width*/,
                              int /*height*/, std::int64_t /*shownNs*/) {}

    // One image whose exposure starts at or after `notBeforeNs` (CLOCK_MONOTONIC), taken as
    // `request` says (a colour request only when colourCapture() is available). Throws
    // ScanError when the camera delivers none.
    virtual CameraImage capture(std::int64_t notBeforeNs, const CaptureRequest& request) = 0;
};

// CLOCK_MONOTONIC now, nanoseconds (the clock of libcamera's timestamps and of page flips).
std::int64_t scanClockNs();
// Sleeps until CLOCK_MONOTONIC reaches `ns` (returns at once when it has).
void sleepUntilNs(std::int64_t ns);

}  // namespace vpe::firmware
