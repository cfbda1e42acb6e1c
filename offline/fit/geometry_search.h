// SPDX-License-Identifier: MIT
// searchGeometryCalibration: finds the camera field of view and light distance that let the
// Fourier BRDF explain a dome capture best. Only the capture's own training images are
// used: a grid of pixels is fitted on three quarters of the lights and scored on the held-
// out quarter in the metric of `vpe eval`, over a coarse grid of hypotheses refined by
// coordinate descent. Two global numbers cannot overfit a capture of thousands of pixels.
#pragma once

#include <vector>

#include "capture/capture.h"
#include "capture/geometry_calibration.h"
#include "normals/normal_map.h"

namespace vpe {

struct GeometrySearchOptions {
    int harmonics = 10;
    double lambda = 3.14;
    unsigned threads = 1;
    int samplePixels = 4096;
    int holdOutEvery = 4;  // every 4th light is held out for scoring
};

struct GeometryHypothesisScore {
    GeometryCalibration calibration;
    double rms = 0;  // held-out RMS, 8-bit sRGB levels
};

struct GeometrySearchResult {
    GeometryCalibration best;
    double bestRms = 0;
    double identityRms = 0;  // orthographic camera, directional lights
    std::vector<GeometryHypothesisScore> scores;
};

GeometrySearchResult searchGeometryCalibration(const Capture& capture, const NormalMap& normals,
                                               const GeometrySearchOptions& options);

}  // namespace vpe
