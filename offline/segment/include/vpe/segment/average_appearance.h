// SPDX-License-Identifier: MIT
// The average appearance of a model, what segmentation looks at: the paper averages the
// photographs over all lights to suppress shading; vpe renders the fitted model under a fixed
// dome of lights instead, so any capture rig gives the same average. Plus a feature vector per
// pixel for clustering: the average colour and the Fourier coefficients, both standardized.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::segment {

struct AppearanceOptions {
    // Principal components of the coefficients kept as features.
    int components = 4;
    // Pixels the principal axes are estimated from (evenly spread): hundreds of samples per
    // covariance entry, and bounded memory and work on big models.
    std::size_t pcaSamples = 50000;
    unsigned threads = 1;
};

struct Appearance {
    int width = 0;
    int height = 0;
    std::size_t validPixels = 0;
    std::vector<std::uint8_t> valid;  // [y][x]
    // Mean linear radiance per unit irradiance over the dome of lights, RGB; 0 where invalid.
    std::vector<float> average;  // [y][x][3]
    // The average colour in CIELAB (D65), what colour distances are measured in.
    std::vector<float> lab;  // [y][x][3]
    // Clustering features: CIELAB and the coefficients' principal components, each group
    // scaled to unit total variance over the valid pixels; 0 where invalid.
    int featureCount = 0;
    std::vector<float> features;  // [y][x][featureCount]
    // Share of the coefficients' variance the kept components explain.
    double explainedVariance = 0;
    std::size_t pixel(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

// The dome the average is taken under: 40 directions spread evenly (equal solid angle) over
// the upper hemisphere of the camera frame, so their mean approximates the average over all
// directions a light can come from.
const std::vector<proto::Vec3d>& averagingLights();

// Reads the model file (twice, band by band: first the average and the principal axes, then
// the projections) and computes the appearance. Throws InputError naming the file.
Appearance computeAppearance(const std::filesystem::path& model, const AppearanceOptions& options);

// CIELAB (D65 white, Y of white = 1) of a linear sRGB colour.
void linearRgbToLab(const float* rgb, float* lab);

}  // namespace vpe::segment
