// SPDX-License-Identifier: MIT
// The board file's [scan] section: how vpe-player --scan shows the structured-light patterns
// and photographs them — the projector's latency, the retries, the camera's fixed exposure and
// stream, the pattern sequence's phase, the frame check's limits, the radiometric capture
// beside the scan, or a simulated camera (boards/README.md, firmware/README.md "Scanning").
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>

#include <toml++/impl/forward_declarations.h>  // toml::table, without the parser

namespace vpe::firmware {

struct ScanConfig {
    // The wait after a pattern is on screen (page flip done) before the camera's exposure may
    // start: the projector's own processing delay, which the host cannot see.
    double latencyMs = 150;
    // Black is shown this long before the first pattern: a projector takes a moment to lock onto
    // a new mode. Unset: 1000 ms on kms, 0 headless (nothing to lock).
    std::optional<double> settleMs;
    // Captures after the first when a frame fails its check, each waiting retryWaitMs longer.
    int retries = 3;
    double retryWaitMs = 100;
    // The camera: fixed exposure and gain (no auto exposure, no auto white balance), and the
    // red and blue colour gains when given; the still stream's size (its Y plane, 8 bits).
    int exposureUs = 20000;
    double analogueGain = 1.0;
    std::optional<std::array<double, 2>> colourGains;
    int cameraWidth = 1640, cameraHeight = 1232;
    // The sequence (proto::StructuredLightParameters): pixels per period, phase steps.
    int phasePeriod = 32;
    int phaseSteps = 8;
    // The frame check: a camera pixel is lit when white − black reaches minContrast of full
    // scale; at least minLitFraction of the pixels must be; a check fails when more than
    // `tolerance` of the lit pixels disagree with what the pattern implies.
    double minContrast = 0.05;
    double minLitFraction = 0.005;
    double tolerance = 0.2;
    // The radiometric capture after the scan (proto::radiometrySequence's flat fields, in colour,
    // into OUT/radiometry/), and its levels per primary.
    bool radiometry = true;
    int radiometryLevels = 16;
    // A simulated camera instead of libcamera: a scene file (vpe synth-procam's
    // installation.toml), resolved against the board file's folder; headless display only.
    std::optional<std::filesystem::path> simulate;
    // Where the control page's install steps write the scan (a radiometric capture alone: its
    // radiometry/ folder), resolved against the board file's folder; unset: "scan" beside the
    // bundle. vpe-player --scan OUT writes OUT.
    std::optional<std::filesystem::path> out;
    // The simulated projector's latency: a capture starting sooner than this after a pattern
    // change sees the pattern before it. Only with `simulate`.
    double simulatedLatencyMs = 0;
};

// Reads the [scan] table strictly: unknown keys, wrong types and values out of range are
// refused with BoardConfigError, one line naming "source:scan.key". `simulate` is resolved
// against the folder of `source` (the board file).
ScanConfig parseScanConfig(const toml::table& scan, const std::string& source);

}  // namespace vpe::firmware
