// SPDX-License-Identifier: MIT
// The `vpe fit` pipeline: decode a band, fit it on all threads, write it.
#include "vpe/fit/capture_fitter.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/seconds_since.h"
#include "vpe/fit/band_fitter.h"
#include "vpe/fit/held_out_search.h"
#include "vpe/fit/rti_band_fitter.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/normals/detail_normals.h"
#include "vpe/normals/normal_source.h"
#include "vpe/normals/photometric_stereo.h"
#include "vpe/preview/relight_preview.h"

namespace vpe::fit {

namespace {

using Clock = std::chrono::steady_clock;

// The first tilt of the extended fit's normal search (then half, then a quarter). On
// realrti-dev 4°, 8° and 12° gave the same held-out PSNR within 0.05 dB on average, and every
// tilt tried costs one more fit of the texel, so the smallest.
constexpr double kNormalSearchDegrees = 4.0;

std::vector<std::uint8_t> readMask(const capture::Capture& capture, int width, int height) {
    if (!capture.mask) {
        return {};
    }
    const image::FloatImage image = image::readImage(*capture.mask);
    if (image.width != width || image.height != height) {
        throw common::InputError(*capture.mask,
                                 "mask size " + std::to_string(image.width) + "x" +
                                     std::to_string(image.height) + " differs from the images' " +
                                     std::to_string(width) + "x" + std::to_string(height));
    }
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < mask.size(); ++i) {
        mask[i] = image.pixels[i * static_cast<std::size_t>(image.channels)] > 0 ? 1 : 0;
    }
    return mask;
}

// The relief the fitted normals carry (refined by the extended fit, or as estimated): each
// row's detail normal against the macro shape, (0, 0, 1) where that is invalid. The macro shape
// is valid only where the normals are.
void fillDetailRows(model::ModelRows& rows, const normals::NormalMap& macro, int rowBegin,
                    const proto::Vec3d& right) {
    const std::size_t first = static_cast<std::size_t>(rowBegin) * macro.width;
    rows.detail.assign(rows.valid.size() * 3, 0.0f);
    for (std::size_t p = 0; p < rows.valid.size(); ++p) {
        const std::size_t m = first + p;
        rows.detail[p * 3 + 2] = 1.0f;
        if (!macro.valid[m]) {
            continue;
        }
        const proto::Vec3d d = normals::detailNormalOf(
            {rows.normal[p * 3], rows.normal[p * 3 + 1], rows.normal[p * 3 + 2]},
            {macro.xyz[m * 3], macro.xyz[m * 3 + 1], macro.xyz[m * 3 + 2]}, right);
        rows.detail[p * 3] = static_cast<float>(d.x);
        rows.detail[p * 3 + 1] = static_cast<float>(d.y);
        rows.detail[p * 3 + 2] = static_cast<float>(d.z);
    }
}

// The RTI bases: no normals, no calibration, the images' stored values fitted as they are.
// Adds a fitted band's valid pixels to the report, and their mean RMS over the channels to
// rmsSum (the report's mean is taken at the end).
void countValid(const model::ModelRows& rows, FitReport& report, double& rmsSum) {
    for (std::size_t p = 0; p < rows.valid.size(); ++p) {
        if (rows.valid[p]) {
            ++report.validPixels;
            for (int c = 0; c < 3; ++c) {
                rmsSum += static_cast<double>(rows.rms[p * 3 + c]) / 3.0;
            }
        }
    }
}

FitReport fitRtiCapture(const capture::Capture& capture, const FitOptions& options,
                        const std::filesystem::path& modelPath) {
    const auto start = Clock::now();
    FitReport report;
    auto decodeStart = Clock::now();
    capture::ImageBandReader reader(capture, options.threads);
    report.decodeSeconds += common::secondsSince(decodeStart);
    report.width = reader.width();
    report.height = reader.height();
    report.images = reader.imageCount();
    report.pixels = static_cast<std::size_t>(report.width) * report.height;
    report.normalsSource = "none (RTI basis)";
    const std::vector<std::uint8_t> mask = readMask(capture, report.width, report.height);
    const fit::RtiBandFitter fitter(capture, options.rtiBasis,
                                    capture::storedTransfer(capture, reader.eightBitCodes()),
                                    options.threads);
    model::ModelInfo info;
    info.width = report.width;
    info.height = report.height;
    info.samples = report.images;
    info.capture = capture.source.string();
    info.variant = options.rtiBasis.kind == model::RtiBasis::Kind::kPtm ? "ptm" : "hsh";
    info.terms = options.rtiBasis.terms;
    model::ModelWriter writer(modelPath, info);
    const int bandRows = reader.rowsForBudget(options.bandBudgetBytes);
    capture::SampleBand band;
    model::ModelRows rows;
    double rmsSum = 0;
    common::ProgressBar progress("fit", static_cast<std::size_t>(report.height));
    for (int rowBegin = 0; rowBegin < report.height; rowBegin += bandRows) {
        const int bandHeight = std::min(bandRows, report.height - rowBegin);
        decodeStart = Clock::now();
        reader.readBand(rowBegin, bandHeight, mask.empty() ? nullptr : mask.data(), band);
        report.decodeSeconds += common::secondsSince(decodeStart);
        const auto fitStart = Clock::now();
        fitter.fit(band, rows);
        countValid(rows, report, rmsSum);
        report.fitSeconds += common::secondsSince(fitStart);
        const auto writeStart = Clock::now();
        writer.writeRows(rowBegin, rows);
        report.writeSeconds += common::secondsSince(writeStart);
        progress.advance(static_cast<std::size_t>(bandHeight));
    }
    progress.finish();
    const auto writeStart = Clock::now();
    writer.finish();
    report.writeSeconds += common::secondsSince(writeStart);
    report.meanRms = report.validPixels ? rmsSum / static_cast<double>(report.validPixels) : 0.0;
    report.totalSeconds = common::secondsSince(start);
    return report;
}

// What can be refused before decoding anything: the options, the output's name, too few images.
void checkFitRequest(const capture::Capture& capture, const FitOptions& options,
                     const std::filesystem::path& modelPath) {
    const bool rti = options.variant == ModelVariant::kRti;
    const int coefficients =
        rti ? options.rtiBasis.terms : proto::coefficientCount(options.harmonics);
    if (options.harmonics < 0 || options.harmonics > proto::kMaxHarmonics) {
        throw common::InputError("--harmonics " + std::to_string(options.harmonics) +
                                 " is out of range (0.." + std::to_string(proto::kMaxHarmonics) +
                                 ")");
    }
    if (!(options.lambda >= 0) || !std::isfinite(options.lambda)) {
        throw common::InputError("--lambda must be a finite number >= 0");
    }
    // Refuse a wrong output name before decoding anything.
    if (modelPath.extension() != ".exr") {
        throw common::InputError(modelPath, "the model file must have the .exr extension");
    }
    if (static_cast<int>(capture.images.size()) < coefficients) {
        throw common::InputError(
            capture.source, std::to_string(capture.images.size()) + " images cannot determine " +
                                std::to_string(coefficients) +
                                (rti ? " coefficients of " + options.rtiBasis.name()
                                     : " coefficients: M = " + std::to_string(options.harmonics) +
                                           " needs N >= 2M + 2 = " + std::to_string(coefficients)));
    }
}

// The camera response, when the capture leaves it unstated (docs/extended-model.md, step 1,
// "Response"): it changes what photometric stereo sees, so the normals are estimated again
// under the response chosen, and the response is chosen again under those normals (once).
// The held-out error decides between the two normal maps too: photometric stereo is a
// Lambertian estimate, and on glossy or shadowed captures a response that fits the radiance
// better can still give worse normals. The searches read normals on their grid alone, so
// photometric stereo runs there for them and on the whole image once, under the response
// whose normals are kept: it had run on the whole image for each (realrti-dev item7: twice
// 0.3-0.45 s). `capture` and `reader` are replaced by those under the response kept; returns
// the normals.
normals::NormalsResult calibrateResponse(capture::Capture& capture,
                                         std::unique_ptr<capture::ImageBandReader>& reader,
                                         const std::vector<std::uint8_t>& mask,
                                         const FitOptions& options, FitReport& report) {
    const auto searchStart = Clock::now();
    HeldOutSearchOptions search;
    search.calibrateResponse = true;
    search.calibrateGeometry = false;
    search.selectRegularization = false;
    search.threads = options.threads;
    const capture::Capture stated = capture;  // the response as the capture states it
    // A given normal map holds whatever the response; photometric stereo's depend on it.
    std::optional<normals::NormalsResult> given;
    if (options.normals || capture.normalMap) {
        given = normals::acquireNormals(capture, options.normals, report.width, report.height,
                                        options.threads);
    }
    const auto searchNormals = [&](const char* stage) {
        if (given) {
            return given->normals;
        }
        const auto normalsStart = Clock::now();
        normals::NormalMap grid = heldOutGridNormals(capture, mask, report.width, report.height,
                                                     search.samplePixels, options.threads);
        report.searchStageSeconds.push_back({stage, common::secondsSince(normalsStart)});
        return grid;
    };
    normals::NormalMap normals = searchNormals("normals on the grid");
    bool statedNormals = true;  // the normals kept are those under the stated response
    for (int round = 0; round < 2; ++round) {
        const HeldOutSearchResult found = searchHeldOut(capture, normals, search);
        for (const SearchStageTime& stage : found.stageSeconds) {
            report.searchStageSeconds.push_back(
                {stage.stage + " (under " + (round == 0 ? "first" : "calibrated") + " normals)",
                 stage.seconds});
        }
        if (round == 1 && found.rms >= report.responseRms) {
            // The normals estimated under the capture's own response predict the held-out
            // lights better: keep them, with the response chosen under them.
            statedNormals = true;
            report.normalsUnderStatedResponse = true;
            break;
        }
        if (round == 0) {  // both under the same (sRGB-estimated) normals
            report.responseRms = found.rms;
            report.statedResponseRms = std::numeric_limits<double>::infinity();
            for (const HeldOutTrial& trial : found.trials) {
                if (trial.calibration.responseGamma == 0) {
                    report.statedResponseRms = std::min(report.statedResponseRms, trial.rms);
                }
            }
        }
        const double gamma = found.calibration.responseGamma;
        if (gamma == 0 || gamma == report.calibration.responseGamma) {
            break;  // the capture's own (sRGB), or what the normals were estimated under
        }
        report.calibration.responseGamma = gamma;
        capture = capture::applyGeometryCalibration(capture, found.calibration, report.width,
                                                    report.height);
        reader = std::make_unique<capture::ImageBandReader>(capture, options.threads);
        statedNormals = false;
        if (round == 0) {
            normals = searchNormals("normals on the grid under the calibrated response");
        }
    }
    report.calibrationSeconds += common::secondsSince(searchStart);
    // The whole map, as the paper's fit estimates it (not the search's time).
    normals::NormalsResult kept =
        given ? std::move(*given)
              : normals::acquireNormals(statedNormals ? stated : capture, options.normals,
                                        report.width, report.height, options.threads);
    if (!given && report.normalsUnderStatedResponse) {
        kept.source += " (estimated under sRGB)";
    }
    return kept;
}

// The relief the normals carry: their mean tilt off the macro shape, in degrees, where the
// macro shape is valid.
double meanReliefDegrees(const normals::NormalMap& normals, const normals::NormalMap& macro,
                         const proto::Vec3d& right) {
    double tilt = 0;
    std::size_t counted = 0;
    for (std::size_t p = 0; p < macro.valid.size(); ++p) {
        if (macro.valid[p]) {
            const proto::Vec3d n{normals.xyz[p * 3], normals.xyz[p * 3 + 1],
                                 normals.xyz[p * 3 + 2]};
            const proto::Vec3d m{macro.xyz[p * 3], macro.xyz[p * 3 + 1], macro.xyz[p * 3 + 2]};
            const float z = static_cast<float>(normals::detailNormalOf(n, m, right).z);
            tilt += std::acos(std::clamp(static_cast<double>(z), -1.0, 1.0));
            ++counted;
        }
    }
    return counted ? tilt / static_cast<double>(counted) * 180.0 / std::numbers::pi : 0;
}

// What the capture cannot state, chosen by the held-out search (docs/extended-model.md, step
// 1): the rig's geometry, M and λ, T's ridge and the blocked lights, each as the options ask.
// Returns the capture under the geometry chosen; M and λ go to the report, as given when not
// selected.
capture::Capture searchUnstated(const capture::Capture& capture, const normals::NormalMap& normals,
                                const FitOptions& options, FitReport& report) {
    report.harmonics = options.harmonics;
    report.lambda = options.lambda;
    const bool extended = options.variant == ModelVariant::kExtended;
    const bool calibrate = extended && capture::acceptsGeometryCalibration(capture);
    if (!calibrate && !options.selectRegularization && !extended) {
        return capture;
    }
    const auto searchStart = Clock::now();
    HeldOutSearchOptions search;
    search.calibrateGeometry = calibrate;
    search.selectRegularization = options.selectRegularization;
    search.selectTransportRidge = extended;
    search.normalSearchDegrees = report.normalSearchDegrees;
    search.calibrateLightIntensities = calibrate;
    search.compareClassicBases = extended;
    search.harmonics = options.harmonics;
    search.lambda = options.lambda;
    search.threads = options.threads;
    const HeldOutSearchResult found = searchHeldOut(capture, normals, search);
    report.calibration.fieldOfViewDegrees = found.calibration.fieldOfViewDegrees;
    report.calibration.lightDistance = found.calibration.lightDistance;
    report.calibration.lightIntensities = found.calibration.lightIntensities;
    report.lightIntensityRms = found.lightIntensityRms;
    report.lightIntensityStatedRms = found.lightIntensityStatedRms;
    report.calibratedRms = found.rms;
    report.uncalibratedRms = found.baselineRms;
    report.harmonics = found.harmonics;
    report.lambda = found.lambda;
    report.transportRidge = found.transportRidge;
    report.transportRms = found.transportRms;
    report.transportTrials = found.transportTrials;
    report.searchStageSeconds.insert(report.searchStageSeconds.end(), found.stageSeconds.begin(),
                                     found.stageSeconds.end());
    report.extendedEveryFold = found.extendedEveryFold;
    report.classicBases = found.classicBases;
    double best = found.extendedEveryFold.imageMean;
    for (const ClassicBasisScore& basis : found.classicBases) {
        if (found.extendedEveryFold.imageMean > 0 && basis.score.imageMean < best) {
            best = basis.score.imageMean;
            report.betterClassicBasis = basis.basis;
        }
    }
    capture::Capture calibrated =
        applyGeometryCalibration(capture, found.calibration, report.width, report.height);
    report.calibrationSeconds += common::secondsSince(searchStart);
    return calibrated;
}

fit::BandFitSettings bandFitSettings(const FitOptions& options, const FitReport& report) {
    fit::BandFitSettings settings;
    settings.fit.harmonics = report.harmonics;
    settings.fit.lambda = report.lambda;
    settings.fit.precision = resolvePrecision(options.precision, report.lambda);
    settings.extended = options.variant == ModelVariant::kExtended;
    if (settings.extended) {  // the search always runs for it, and chose the ridge
        settings.fit.transportRidge = report.transportRidge;
        settings.fit.normalSearchDegrees = report.normalSearchDegrees;
    }
    settings.threads = options.threads;
    return settings;
}

model::ModelInfo fittedModelInfo(const capture::Capture& capture, const FitOptions& options,
                                 const FitReport& report) {
    model::ModelInfo info = model::fourierModelInfo(report.width, report.height, report.harmonics,
                                                    report.lambda, report.images);
    info.capture = capture.source.string();
    info.variant = options.variant == ModelVariant::kExtended ? "extended" : "paper";
    info.calibration = report.calibration;
    info.texelMm = capture.texelMm.value_or(0.0);
    info.storage = options.storage;
    info.detailNormals = options.relief == ReliefMode::kDetailMap;
    return info;
}

// Decodes, fits and writes the capture band by band (a band as many rows as the memory budget
// holds), with the relief's detail normals and the preview; the bar shows the step under way
// and the time each kind of step has taken.
void fitBandByBand(capture::ImageBandReader& reader, const std::vector<std::uint8_t>& mask,
                   const fit::BandFitter& fitter, model::ModelWriter& writer,
                   const model::ModelInfo& info, const normals::NormalMap& macro,
                   const proto::Vec3d& right, const FitOptions& options,
                   const std::filesystem::path& modelPath, FitReport& report) {
    preview::RelightPreview preview(report.width, report.height, info.harmonics);
    const int bandRows = reader.rowsForBudget(options.bandBudgetBytes);
    capture::SampleBand band;
    model::ModelRows rows;
    double rmsSum = 0;
    common::ProgressBar progress("fit", static_cast<std::size_t>(report.height));
    auto showPhase = [&](const char* phase) {
        progress.setPhase(phase, {{"decode", report.decodeSeconds},
                                  {"fit", report.fitSeconds},
                                  {"write", report.writeSeconds}});
    };
    for (int rowBegin = 0; rowBegin < report.height; rowBegin += bandRows) {
        const int bandHeight = std::min(bandRows, report.height - rowBegin);
        showPhase("decoding");
        const auto decodeStart = Clock::now();
        reader.readBand(rowBegin, bandHeight, mask.empty() ? nullptr : mask.data(), band);
        report.decodeSeconds += common::secondsSince(decodeStart);

        showPhase("fitting");
        const auto fitStart = Clock::now();
        fitter.fit(band, rows);
        if (info.detailNormals) {
            fillDetailRows(rows, macro, rowBegin, right);
        }
        countValid(rows, report, rmsSum);
        report.fitSeconds += common::secondsSince(fitStart);

        showPhase("writing");
        const auto writeStart = Clock::now();
        writer.writeRows(rowBegin, rows);
        if (options.writePreview) {
            preview.addRows(rowBegin, rows);
        }
        report.writeSeconds += common::secondsSince(writeStart);
        progress.advance(static_cast<std::size_t>(bandHeight));
    }
    showPhase("finishing");
    const auto writeStart = Clock::now();
    writer.finish();
    if (options.writePreview) {
        report.preview = modelPath;
        report.preview.replace_extension(".preview.png");
        preview.write(report.preview);
    }
    report.writeSeconds += common::secondsSince(writeStart);
    showPhase("done");
    progress.finish();
    report.meanRms = report.validPixels ? rmsSum / static_cast<double>(report.validPixels) : 0.0;
}

}  // namespace

fit::AccumulationPrecision resolvePrecision(FitPrecision precision, double lambda) {
    switch (precision) {
        case FitPrecision::kFast:
            return fit::AccumulationPrecision::kFloatBlocks;
        case FitPrecision::kExact:
            return fit::AccumulationPrecision::kDouble;
        case FitPrecision::kAuto:
            break;
    }
    return lambda < 1e-3 ? fit::AccumulationPrecision::kDouble
                         : fit::AccumulationPrecision::kFloatBlocks;
}

// docs/extended-model.md, "How it is fitted", in order: the response with the normals, the
// relief, the held-out search, then the fit itself band by band.
FitReport fitCapture(const capture::Capture& originalCapture, const FitOptions& options,
                     const std::filesystem::path& modelPath) {
    const auto start = Clock::now();
    checkFitRequest(originalCapture, options, modelPath);
    if (options.variant == ModelVariant::kRti) {
        return fitRtiCapture(originalCapture, options, modelPath);
    }

    FitReport report;
    const auto decodeStart = Clock::now();
    auto reader = std::make_unique<capture::ImageBandReader>(originalCapture, options.threads);
    report.decodeSeconds += common::secondsSince(decodeStart);
    report.width = reader->width();
    report.height = reader->height();
    report.images = reader->imageCount();
    report.pixels = static_cast<std::size_t>(report.width) * report.height;
    const std::vector<std::uint8_t> mask = readMask(originalCapture, report.width, report.height);

    const bool extended = options.variant == ModelVariant::kExtended;
    capture::Capture capture = originalCapture;
    const auto normalsStart = Clock::now();
    normals::NormalsResult normals =
        extended && options.calibrateResponse && capture::acceptsResponseCalibration(capture) &&
                reader->eightBitCodes()
            ? calibrateResponse(capture, reader, mask, options, report)
            : normals::acquireNormals(capture, options.normals, report.width, report.height,
                                      options.threads);
    report.normalsSource = normals.source;
    // The relief: measured against the macro shape, then either carried as a detail map or
    // left for the coefficients (fitted against the macro normals).
    report.macroSigma =
        options.macroSigma.value_or(normals::defaultMacroSigma(report.width, report.height));
    const normals::NormalMap macro = normals::lowPassNormals(normals.normals, report.macroSigma);
    const proto::Vec3d right = normals::imageRightDirection(originalCapture);
    report.meanReliefDegrees = meanReliefDegrees(normals.normals, macro, right);
    if (options.relief == ReliefMode::kInCoefficients) {
        normals.normals = macro;
    }
    report.normalsSeconds = common::secondsSince(normalsStart);

    // The extended fit refines photometric stereo's normals, a Lambertian estimate that leaves
    // out the darkest samples, where raking lights are most sensitive to the tilt. A given
    // normal map is trusted, as a manifest's geometry is; in coefficients mode the normals are
    // the macro shape by design.
    if (extended && normals.estimated && options.relief == ReliefMode::kDetailMap) {
        report.normalSearchDegrees = kNormalSearchDegrees;
        report.normalsSource += ", refined by the fit";
    }
    capture = searchUnstated(capture, normals.normals, options, report);
    if (options.fallBackToClassicBasis && !report.betterClassicBasis.empty()) {
        // What RTI tools would fit predicts this capture better: write that, and say so.
        FitOptions classic = options;
        classic.variant = ModelVariant::kRti;
        classic.rtiBasis = *model::RtiBasis::parse(report.betterClassicBasis);
        FitReport fallen = fitRtiCapture(originalCapture, classic, modelPath);
        fallen.extendedEveryFold = report.extendedEveryFold;
        fallen.classicBases = report.classicBases;
        fallen.betterClassicBasis = report.betterClassicBasis;
        fallen.fellBackToClassicBasis = true;
        fallen.totalSeconds = common::secondsSince(start);
        return fallen;
    }

    const capture::SurfaceGeometry geometry(capture, report.width, report.height);
    const fit::BandFitter fitter(capture, geometry, normals.normals,
                                 bandFitSettings(options, report));
    const model::ModelInfo info = fittedModelInfo(capture, options, report);
    model::ModelWriter writer(modelPath, info, options.threads);
    fitBandByBand(*reader, mask, fitter, writer, info, macro, right, options, modelPath, report);
    report.totalSeconds = common::secondsSince(start);
    return report;
}

}  // namespace vpe::fit
