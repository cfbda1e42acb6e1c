// SPDX-License-Identifier: MIT
// exportModelToRelight: a fitted model as a Relight web RTI — the model relit at the
// capture's view under the bilinear grid's lights (CapturePredictor, as `vpe eval` predicts),
// encoded by writeRelightWeb — then read back and compared with the model's own predictions
// under the capture's lights, so every export states what it lost.
#pragma once

#include <filesystem>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/relight_web/relight_web_encoder.h"

namespace vpe::relight_web {

struct RelightRoundTrip {
    int lights = 0;                // capture lights compared
    std::size_t pixels = 0;        // pixels with a valid fit, compared in each
    double psnr = 0;               // mean over lights of the per-light PSNR (sRGB, [0, 1])
    double worstPsnr = 0;          // the lowest of them
    std::vector<double> perLight;  // PSNR under each check light, in the capture's order
};

struct RelightModelExport {
    RelightWebSummary summary;
    RelightRoundTrip roundTrip;
};

// `checkLights` are the lights the round trip compares under (e.g. the capture's held-out
// ones); empty means all of the capture's lights. Throws InputError for bad inputs.
RelightModelExport exportModelToRelight(const std::filesystem::path& modelPath,
                                        const capture::Capture& capture,
                                        const std::filesystem::path& folder,
                                        const RelightWebOptions& options,
                                        const capture::Capture& checkLights);

}  // namespace vpe::relight_web
