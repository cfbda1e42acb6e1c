// SPDX-License-Identifier: MIT
// Simulated captures on disk: a scan folder exactly as vpe-player --scan writes one
// (proto/SCAN.md), rendered by the projector–camera simulator, and the truth files beside it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "vpe/common/progress_bar.h"
#include "vpe/proto/structured_light.h"
#include "vpe/renderer/procam/procam_simulator.h"

namespace vpe::procam {

struct SimulatedScanOptions {
    int phasePeriod = 32;
    int phaseSteps = 8;
    // Frames are numbered from here for the noise, so that two captures differ.
    std::uint64_t firstFrame = 0;
    std::string source = "simulated";  // the manifest's camera.source
};

// Renders every pattern of the sequence for the simulator's projector, exposes it and writes
// NNN-<pattern>.pgm (8 or 10 bits, as the camera) and scan.json into `folder` (created; its
// former pattern images and manifest are replaced). `progress` advances once per image when
// given.
void writeSimulatedScan(const renderer::procam::ProcamSimulator& simulator,
                        const std::filesystem::path& folder, const SimulatedScanOptions& options,
                        common::ProgressBar* progress = nullptr);

struct SimulatedRadiometryOptions {
    int levels = 16;  // per primary (proto::RadiometryParameters::levels)
    // Frames are numbered from here for the noise (after the scan's own).
    std::uint64_t firstFrame = 1000;
    std::string source = "simulated";
};

// The radiometric capture (proto/RADIOMETRY.md) the device takes beside the scan: every flat
// field of the sequence rendered for the simulator's projector and photographed in colour by its
// camera's sensor (the same optics, exposure, noise and response; RGB), the ramp at its bracket's
// exposures when the camera's response is not linear; NNN-<name>.ppm and radiometry.json in
// `folder`. An 8-bit sensor when the response is a gamma (the bracket reads 8-bit codes).
void writeSimulatedRadiometry(const renderer::procam::ProcamSimulator& simulator,
                              const std::filesystem::path& folder,
                              const SimulatedRadiometryOptions& options,
                              common::ProgressBar* progress = nullptr);

// The truth of the simulator's installation, in the camera's frame:
//   camera-truth.exr: per camera pixel, the projector coordinate it sees (projector.x/y: the
//     light-weighted mean over its area, CameraTruth), its centre ray's (centre.x/y) and the
//     point that ray meets (point.X/Y/Z); NaN elsewhere;
//   projector-truth.exr: per projector pixel, the point it lights (position.X/Y/Z), the normal
//     there (normal.X/Y/Z) and whether the camera sees it (seen, 0 or 1);
//   calibration.yml: the true projector and camera as vpe calibrate writes them.
void writeSimulationTruth(const renderer::procam::ProcamSimulator& simulator,
                          const std::filesystem::path& folder);

}  // namespace vpe::procam
