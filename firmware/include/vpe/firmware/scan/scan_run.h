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
//
// runCapture is that capture with the camera and the display opened by its caller: runScan
// (--scan) opens them itself, the player lends its own display for the control page's install
// steps (install_capture.h); both run the same sequence, checks and folder.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vpe/firmware/board/board_config.h"
#include "vpe/firmware/player/player_options.h"
#include "vpe/firmware/scan/capture_loop.h"
#include "vpe/firmware/scan/frame_check.h"
#include "vpe/firmware/scan/install_images.h"
#include "vpe/firmware/scan/radiometric_capture.h"
#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/firmware/scan/scan_folder.h"
#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::firmware {

enum class CaptureKind : std::uint8_t {
    kScan,        // the patterns, then the radiometric capture unless [scan] radiometry = false
    kRadiometry,  // the radiometric capture's flat fields alone, into OUT/radiometry/
};

struct ScanReport {
    CaptureKind kind = CaptureKind::kScan;
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

// What a capture tells its caller as it goes (the control page's install steps).
struct CaptureProgress {
    std::string step;       // the image just accepted ("gray-x-b8", "radiometry: red-3")
    std::size_t done = 0;   // images accepted
    std::size_t total = 0;  // images of the whole capture (the radiometry's included)
};

struct CaptureObserver {
    std::function<void(const CaptureProgress&)> progress;  // after each accepted image
    // The camera's view of the white pattern (or the white flat field), once accepted.
    std::function<void(const CameraImage&)> cameraView;
    // The coverage map once the captures are in (before the folder is moved into place).
    std::function<void(const CoverageMap&)> coverage;
};

// What runCapture draws on and photographs with, opened by its caller.
struct CaptureStage {
    ScanCamera& camera;
    renderer::gles::RenderTarget& target;  // the patterns' (the projector's) size
    std::string platform;                  // its description, for the report
    // Asked between captures and during waits: why to stop, empty to go on.
    CaptureLoop::Interrupted interrupted;
};

// The camera [scan] asks for: the simulation, or the lamp's camera ([camera] id, enabled) on a
// projector (kms). Throws PlayerInputError (no [scan], a camera disabled, absent or in use).
std::unique_ptr<ScanCamera> openScanCamera(const BoardConfig& board);

// The patterns' size on `platform`: the display's mode (KMS), else --size, the board's render
// size, or the simulated projector's. Throws PlayerInputError when they disagree.
std::array<int, 2> scanProjectorSize(const renderer::gles::GraphicsPlatform& platform,
                                     const PlayerOptions& options, const BoardConfig& board,
                                     const ScanCamera& camera);

// The capture into `folder` (a ScanFolder for OUT; for kRadiometry one for OUT/radiometry with
// radiometry.json as its manifest), committed at the end. The [scan] section is the board's.
// Throws as runScan does.
ScanReport runCapture(const BoardConfig& board, CaptureKind kind, ScanFolder& folder,
                      CaptureStage& stage, const CaptureObserver& observer = {});

// Throws PlayerInputError (exit 2: no [scan] section, the camera disabled or absent, a display
// that cannot be opened, an OUT that is not a scan folder, a bad scene file), ScanError (exit
// 1: a pattern whose captures kept failing the check, a camera that stopped; nothing is
// written), BoardConfigError ([camera] read strictly).
ScanReport runScan(const PlayerOptions& options, const BoardConfig& board,
                   std::int64_t processStartNs);

}  // namespace vpe::firmware
