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

// Per-light PSNR (sRGB, [0, 1]) under the check lights, over the pixels with a valid fit.
struct LightPsnrs {
    double mean = 0;               // mean over lights
    double worst = 0;              // the lowest
    std::vector<double> perLight;  // in the check capture's order
};

// Decoded values below 0 at the grid's nodes: where OpenLIME's pow() is undefined.
struct NegativeDecodes {
    std::size_t values = 0;  // pixel · channel · node values below 0
    std::size_t pixels = 0;  // pixels with one below 0 at some node
    int nodes = 0;           // nodes where some value is below 0
    double lowest = 0;       // the lowest value decoded at a node, in any pixel
};

struct RelightRoundTrip {
    int lights = 0;          // capture lights compared
    std::size_t pixels = 0;  // pixels with a valid fit, compared in each
    // The export as OpenLIME shows it (openlime_display.h: linear light in an 8-bit buffer):
    // what a viewer sees, against the model's prediction.
    LightPsnrs viewer;
    // The decoded values clamped to [0, 1], no display step: what the export holds.
    LightPsnrs decoded;
    // The model's own prediction through OpenLIME's display: the most a viewer can see of the
    // model at all, whatever the encoding.
    LightPsnrs displayOnly;
    NegativeDecodes negative;  // over every pixel, valid or not, at every grid node
};

struct RelightModelExport {
    RelightWebSummary summary;
    RelightRoundTrip roundTrip;
};

// `checkLights` are the lights the round trip compares under (e.g. the capture's held-out
// ones); empty means all of the capture's lights. Throws common::InputError for bad inputs.
RelightModelExport exportModelToRelight(const std::filesystem::path& modelPath,
                                        const capture::Capture& capture,
                                        const std::filesystem::path& folder,
                                        const RelightWebOptions& options,
                                        const capture::Capture& checkLights);

}  // namespace vpe::relight_web
