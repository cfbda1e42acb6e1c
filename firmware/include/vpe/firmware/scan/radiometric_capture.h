// SPDX-License-Identifier: MIT
// captureRadiometry: the radiometric capture vpe-player --scan takes after the structured-light
// patterns, in the same session — the flat fields of proto::radiometrySequence (black, white,
// each primary up a ladder of levels, and a ramp at bracketed exposures when the camera's
// response is unknown) shown in RGB, photographed in colour through the scan's CaptureLoop and
// checked by FlatFieldCheck, written as OUT/radiometry/NNN-<name>.ppm and radiometry.json
// (proto/include/vpe/proto/radiometry_capture.h), what `vpe radiometry` reads.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "vpe/firmware/scan/capture_loop.h"
#include "vpe/firmware/scan/frame_check.h"
#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/proto/radiometry_capture.h"

namespace vpe::firmware {

struct RadiometrySettings {
    int projectorWidth = 0, projectorHeight = 0;
    int levels = 16;  // per primary
    FrameCheckSettings check;
    // One frame's noise in the scan's captures (ScanFrameCheck::noiseSigma) and their depth:
    // the flat-field check's noise, scaled to the colour captures' depth.
    double scanNoiseSigma = 0;
    int scanMaxValue = 255;
};

struct RadiometryReport {
    bool captured = false;
    std::string skipped;  // why not, when not captured
    ColourCapture colour;
    std::size_t fields = 0;
    CaptureTally tally;
    double litFraction = 0;  // of the colour captures' white − black
    double seconds = 0;      // black shown → radiometry.json written
};

// Told of each flat field once accepted (the control page's progress and camera view).
struct RadiometryObserver {
    std::function<void(const proto::FlatField& field, const CameraImage& image)> accepted;
};

// Shows black for the loop's wait (the projector showed the scan's last pattern), then every
// flat field in FlatFieldCheck's order, each captured in colour at the exposure × its
// exposureScale() through `loop`, and writes the images (in the sequence's order) and the
// manifest into `folder` (created). `colour` is camera.colourCapture(), available. Throws
// ScanError as the loop does (a field whose captures kept failing, a signal), and
// PlayerInputError for a projector size the sequence refuses.
RadiometryReport captureRadiometry(CaptureLoop& loop, const ScanCamera& camera,
                                   const ColourCapture& colour, const RadiometrySettings& settings,
                                   const std::filesystem::path& folder,
                                   const RadiometryObserver& observer = {});

}  // namespace vpe::firmware
