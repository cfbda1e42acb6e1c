// SPDX-License-Identifier: MIT
// evaluateModel: predicts every image of a capture from a model (the capture's lights and
// camera, the model's normals) and scores it the way people see it: prediction clamped to
// [0, 1] in linear radiance, sRGB-encoded, compared with the sRGB-encoded image (for a model
// fitted under a calibrated camera response: both in the images' stored values), PSNR =
// 10·log10(1/MSE) on [0, 1] and RMS in 8-bit levels. Only pixels the model holds a valid fit
// for are scored; their count is reported.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::eval {

struct ImageScore {
    std::string name;
    double mse = 0;   // on [0, 1] sRGB values, over scored pixels and channels
    double rms = 0;   // in 8-bit levels: √MSE · 255
    double psnr = 0;  // dB
};

struct EvaluationReport {
    std::vector<ImageScore> images;
    double rms = 0;                 // pooled over all images, 8-bit levels
    double psnr = 0;                // mean of the per-image PSNRs (the RTI literature's convention)
    double psnrPooled = 0;          // 10·log10(1/pooled MSE)
    std::size_t pixels = 0;         // scored per image
    std::size_t skippedPixels = 0;  // without a valid fit, or masked
};

struct EvaluationOptions {
    unsigned threads = 1;
    std::optional<std::filesystem::path> predictionsDir;  // writes <image stem>.png there
};

EvaluationReport evaluateModel(const std::filesystem::path& modelPath,
                               const capture::Capture& capture, const EvaluationOptions& options);

double psnrFromMse(double mse);

}  // namespace vpe::eval
