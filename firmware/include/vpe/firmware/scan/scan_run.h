// SPDX-License-Identifier: MIT
// runScan: vpe-player --scan OUT. The board's display shows every pattern of the structured-
// light sequence full-screen; after the projector's latency the camera captures one frame; the
// frame check compares it with what the pattern implies and, when it fails, the pattern group
// is shown again and captured after a longer wait (the wait that worked is kept for the rest);
// the images and scan.json (proto/SCAN.md) go into a temporary folder renamed to OUT at the
// end. What `vpe scan` and `vpe calibrate` read (firmware/README.md, "Scanning"). Then, in the
// same session and through the same loop, the radiometric capture's flat fields in colour
// (radiometric_capture.h) into OUT/radiometry/, unless [scan] radiometry is false or the camera
// cannot photograph them in colour (one line says why; the scan is written all the same).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vpe/firmware/board_config.h"
#include "vpe/firmware/player_options.h"
#include "vpe/firmware/scan/frame_check.h"
#include "vpe/firmware/scan/radiometric_capture.h"
#include "vpe/firmware/scan/scan_camera.h"

namespace vpe::firmware {

struct ScanReport {
    std::filesystem::path out;
    std::string platform;
    ScanCameraInfo camera;
    int projectorWidth = 0, projectorHeight = 0;
    int phasePeriod = 0, phaseSteps = 0;
    std::size_t patterns = 0;
    std::size_t captures = 0;  // every capture, retries included
    std::size_t retried = 0;   // images that took more than one capture
    std::array<std::uint64_t, kFrameProblemCount> rejected{};  // captures refused, per problem
    double latencyMs = 0;                                      // the board's wait after a pattern
    double waitMs = 0;  // the wait in use at the end (longer when retries needed it)
    bool simulated = false;
    double simulatedLatencyMs = 0;
    double litFraction = 0;         // the camera's pixels that white lights
    double noiseSigma = 0;          // one frame's noise, samples (the frame check's estimate)
    double cameraSetupMs = 0;       // opening the camera (simulated: reading and tracing the scene)
    double displaySetupMs = 0;      // the display platform and its target
    std::vector<double> captureMs;  // per capture: pattern on screen → image in hand
    double scanSeconds = 0;         // the first pattern shown → OUT in place
    double seconds = 0;             // process start → OUT in place
    RadiometryReport radiometry;    // the flat fields after the patterns, or why none

    // "scan: 40 patterns, 40 captures (0 retried) in 2.1 s → OUT (…); radiometry: 50 flat
    // fields, 50 captures (0 retried), linear" (or "radiometry: none").
    std::string summaryLine() const;
    // One JSON object (firmware/README.md, "Scanning").
    std::string json() const;
};

// Throws PlayerInputError (exit 2: no [scan] section, the camera disabled or absent, a display
// that cannot be opened, an OUT that is not a scan folder, a bad scene file), ScanError (exit
// 1: a pattern whose captures kept failing the check, a camera that stopped; nothing is
// written), BoardConfigError ([camera] read strictly).
ScanReport runScan(const PlayerOptions& options, const BoardConfig& board,
                   std::int64_t processStartNs);

}  // namespace vpe::firmware
