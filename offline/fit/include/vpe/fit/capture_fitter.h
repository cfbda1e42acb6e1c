// SPDX-License-Identifier: MIT
// fitCapture: the `vpe fit` pipeline. Streams the capture in bands of rows, fits every
// pixel's Fourier BRDF (paper eq. 16–19) on all threads and writes the model file band by
// band, so memory stays bounded whatever the number and size of the images.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/geometry_calibration.h"
#include "vpe/fit/held_out_search.h"
#include "vpe/fit/normal_equations.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/rti_basis.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::fit {

enum class FitPrecision {
    kAuto,   // exact for unregularized fits (λ < 1e-3), fast otherwise
    kFast,   // float accumulation blocks
    kExact,  // double accumulation
};

enum class ModelVariant {
    kPaper,     // the paper's fit, exactly (eq. 16–19) under the capture's stated geometry
    kExtended,  // also calibrates the capture geometry (see docs/extended-model.md)
    kRti,       // a classic RTI basis (FitOptions::rtiBasis), for comparison; not a BRDF
};

// What becomes of the relief — the part of the normals the macro shape (the normals
// low-passed) does not explain (docs/transfer-fidelity.md compares the two).
enum class ReliefMode {
    // Fit against the per-pixel normals and write the relief as a detail normal map
    // (detail.X/Y/Z) that travels with the texels and tilts the screen object's normals.
    kDetailMap,
    // Fit against the macro normals: the coefficients absorb the relief's shading as far as a
    // function of (θd, θs) can; no detail map.
    kInCoefficients,
};

struct FitOptions {
    ModelVariant variant = ModelVariant::kPaper;
    model::RtiBasis rtiBasis;  // kRti only
    // Choose M and λ by held-out validation on the training lights instead of using the
    // values below (the CLI does so for the extended model unless they are given).
    bool selectRegularization = false;
    // Extended variant: calibrate the camera response of 8-bit images whose encoding the
    // capture leaves unstated (held-out search); false keeps sRGB.
    bool calibrateResponse = true;
    // Extended variant: where a classic RTI basis predicts the capture's own training lights
    // better than the extended model (every fold, vpe eval's figure), fit and write that basis
    // instead. Off, the fit only says so.
    bool fallBackToClassicBasis = false;
    int harmonics = proto::kDefaultHarmonics;
    double lambda = proto::kDefaultLambda;
    unsigned threads = 1;
    FitPrecision precision = FitPrecision::kAuto;
    std::optional<std::filesystem::path> normals;
    ReliefMode relief = ReliefMode::kDetailMap;
    // σ of the low-pass that gives the macro shape, pixels; unset: defaultMacroSigma.
    std::optional<double> macroSigma;
    std::size_t bandBudgetBytes = std::size_t{192} << 20;  // decoded samples held at once
    bool writePreview = true;
    model::ModelStorage storage = model::ModelStorage::kFloat;  // the model file's channels
};

struct FitReport {
    std::size_t pixels = 0;
    std::size_t validPixels = 0;
    int images = 0;
    int width = 0;
    int height = 0;
    std::string normalsSource;
    double macroSigma = 0;         // pixels
    double meanReliefDegrees = 0;  // mean tilt of the per-pixel normals off the macro shape
    double normalsSeconds = 0;
    double decodeSeconds = 0;
    double fitSeconds = 0;
    double writeSeconds = 0;
    double totalSeconds = 0;
    double meanRms = 0;  // residual RMS over valid pixels, linear, unit irradiance
    int harmonics = 0;   // as fitted (selected, or as given)
    double lambda = 0;
    std::filesystem::path preview;
    // Held-out search (extended variant): the calibration and regularization found, and
    // the held-out RMS against that of the stated geometry with the given M and λ.
    capture::GeometryCalibration calibration;
    double calibrationSeconds = 0;
    double calibratedRms = 0;
    double uncalibratedRms = 0;
    // The response stage (8-bit images of unstated encoding): held-out RMS in stored values
    // under the response chosen and under sRGB, at the stated geometry, each at its best M, λ.
    double responseRms = 0;
    double statedResponseRms = 0;
    // The normals re-estimated under the response chosen predicted the held-out lights worse
    // than those estimated under sRGB, so the fit kept the latter.
    bool normalsUnderStatedResponse = false;
    // The extended model's light transport: the ridge towards T ≡ 1 chosen by the held-out
    // extended fit, and that fit's held-out RMS (8-bit levels).
    double transportRidge = 0;
    double transportRms = 0;
    std::vector<TransportRidgeTrial> transportTrials;
    // Where the search's time went (calibrationSeconds): the response search per round, the
    // normals estimated again under a calibrated response, the unstated search's stages.
    std::vector<SearchStageTime> searchStageSeconds;
    // Blocked lights (HeldOutSearchResult::lightIntensityRms): the held-out per-image RMS over
    // every fold of the extended fit with and without them (0: not tried);
    // calibration.lightIntensities holds them when they predicted better.
    double lightIntensityRms = 0;
    double lightIntensityStatedRms = 0;
    // Photometric-stereo normals refined by the extended fit: its normal search's first tilt
    // (0: the normals as estimated or given).
    double normalSearchDegrees = 0;
    // The extended model as chosen and the classic bases on every fold of the training lights
    // (HeldOutSearchResult); the basis that beat the extended model there, if one did (by the
    // images' mean RMS), and whether the fit wrote it instead (fallBackToClassicBasis).
    HeldOutScore extendedEveryFold;
    std::vector<ClassicBasisScore> classicBases;
    std::string betterClassicBasis;
    bool fellBackToClassicBasis = false;
};

fit::AccumulationPrecision resolvePrecision(FitPrecision precision, double lambda);

FitReport fitCapture(const capture::Capture& capture, const FitOptions& options,
                     const std::filesystem::path& modelPath);

}  // namespace vpe::fit
