// SPDX-License-Identifier: MIT
// Held-out evaluation of a model.
#include "vpe/eval/model_evaluation.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/light_transport.h"
#include "vpe/model/rti_basis.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe {

double psnrFromMse(double mse) {
    // A perfect prediction is capped at 100 dB rather than infinity, so JSON stays numeric.
    return mse > 1e-10 ? 10.0 * std::log10(1.0 / mse) : 100.0;
}

EvaluationReport evaluateModel(const std::filesystem::path& modelPath, const Capture& statedCapture,
                               const EvaluationOptions& options) {
    ModelReader model(modelPath, ModelKinds::kAny);
    const ModelInfo& info = model.info();
    const std::optional<RtiBasis> rti = info.rtiBasis();
    ImageBandReader reader(statedCapture, options.threads);
    // A model fitted under a calibrated geometry predicts other captures of the same dome
    // under that geometry too.
    const Capture capture =
        acceptsGeometryCalibration(statedCapture)
            ? applyGeometryCalibration(statedCapture, info.calibration, info.width, info.height)
            : statedCapture;
    // Prediction and truth are compared sRGB-encoded, as people see them. An RTI basis
    // predicts the stored values, which are decoded first.
    const TransferFunction metric{TransferFunction::Kind::kSrgb};
    const TransferFunction stored = storedTransfer(capture, reader.eightBitCodes());
    std::vector<double> rtiBasisValues;
    if (rti) {
        rtiBasisValues.resize(capture.images.size() * static_cast<std::size_t>(rti->terms));
        for (std::size_t s = 0; s < capture.images.size(); ++s) {
            rti->evaluate(capture.images[s].light,
                          &rtiBasisValues[s * static_cast<std::size_t>(rti->terms)]);
        }
    }
    if (reader.width() != info.width || reader.height() != info.height) {
        throw InputError(capture.source, "images are " + std::to_string(reader.width()) + "x" +
                                             std::to_string(reader.height()) + " but the model " +
                                             modelPath.string() + " is " +
                                             std::to_string(info.width) + "x" +
                                             std::to_string(info.height));
    }
    const int width = info.width;
    const int height = info.height;
    const int imageCount = reader.imageCount();
    const SurfaceGeometry geometry(capture, width, height);  // normals come from the model

    std::vector<std::vector<std::uint8_t>> predictions;
    if (options.predictionsDir) {
        predictions.assign(
            static_cast<std::size_t>(imageCount),
            std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3, 0));
    }
    std::vector<double> squaredError(static_cast<std::size_t>(imageCount), 0.0);
    std::size_t scored = 0;
    std::mutex mergeMutex;

    const int bandRows = reader.rowsForBudget(std::size_t{128} << 20);
    SampleBand band;
    ModelRows rows;
    ProgressBar progress("eval", static_cast<std::size_t>(height));
    for (int rowBegin = 0; rowBegin < height; rowBegin += bandRows) {
        const int bandHeight = std::min(bandRows, height - rowBegin);
        reader.readBand(rowBegin, bandHeight, nullptr, band);
        model.readRows(rowBegin, bandHeight, rows);
        parallelFor(
            static_cast<std::size_t>(bandHeight), 1, options.threads,
            [&](std::size_t begin, std::size_t end) {
                std::vector<double> localError(static_cast<std::size_t>(imageCount), 0.0);
                std::size_t localScored = 0;
                auto score = [&](int s, int y, int x, int c, double p8, double t8) {
                    localError[static_cast<std::size_t>(s)] += (p8 - t8) * (p8 - t8);
                    if (!predictions.empty()) {
                        predictions[static_cast<std::size_t>(s)]
                                   [(static_cast<std::size_t>(y) * width + x) * 3 + c] =
                                       static_cast<std::uint8_t>(std::lround(p8 * 255));
                    }
                };
                for (std::size_t r = begin; r < end; ++r) {
                    const int row = static_cast<int>(r);
                    const int y = rowBegin + row;
                    for (int x = 0; x < width; ++x) {
                        const std::size_t p = rows.pixel(row, x);
                        if (!rows.valid[p]) {
                            continue;
                        }
                        ++localScored;
                        if (rti) {
                            for (int s = 0; s < imageCount; ++s) {
                                const double* basis =
                                    &rtiBasisValues[static_cast<std::size_t>(s) * rti->terms];
                                for (int c = 0; c < 3; ++c) {
                                    const float* coefficients = rows.coefficientsAt(row, x, c);
                                    double value = 0;
                                    for (int k = 0; k < rti->terms; ++k) {
                                        value += basis[k] * static_cast<double>(coefficients[k]);
                                    }
                                    const double p8 =
                                        metric.encode(std::clamp(stored.decode(value), 0.0, 1.0));
                                    const double t8 = metric.encode(std::clamp(
                                        static_cast<double>(band.value(s, c, row, x)), 0.0, 1.0));
                                    score(s, y, x, c, p8, t8);
                                }
                            }
                            continue;
                        }
                        const Vec3d normal{rows.normal[p * 3], rows.normal[p * 3 + 1],
                                           rows.normal[p * 3 + 2]};
                        const Vec3d view = geometry.toViewer(x, y);
                        const Vec3d position = geometry.position(x, y);
                        for (int s = 0; s < imageCount; ++s) {
                            const IncidentLight light = incidentLight(
                                capture, capture.images[static_cast<std::size_t>(s)], position);
                            const auto angles =
                                proto::reflectionAngles(normal, light.direction, view);
                            // The extended model's capture-specific light transport (cast
                            // shadows, interreflection) of this texel under this light.
                            const double transport =
                                rows.transport.empty()
                                    ? 1.0
                                    : std::max(
                                          0.0,
                                          evaluateLightTransport(
                                              &rows.transport[p * kTransportTerms],
                                              transportDirection(
                                                  capture,
                                                  capture.images[static_cast<std::size_t>(s)])));
                            for (int c = 0; c < 3; ++c) {
                                const double predicted =
                                    transport * light.irradiance *
                                    proto::evaluateFourierBrdf(rows.coefficientsAt(row, x, c),
                                                               info.harmonics, angles.cosThetaD,
                                                               angles.cosThetaS);
                                const double p8 = metric.encode(std::clamp(predicted, 0.0, 1.0));
                                const double t8 = metric.encode(std::clamp(
                                    static_cast<double>(band.value(s, c, row, x)), 0.0, 1.0));
                                score(s, y, x, c, p8, t8);
                            }
                        }
                    }
                }
                std::lock_guard lock(mergeMutex);
                for (int s = 0; s < imageCount; ++s) {
                    squaredError[static_cast<std::size_t>(s)] +=
                        localError[static_cast<std::size_t>(s)];
                }
                scored += localScored;
            });
        progress.advance(static_cast<std::size_t>(bandHeight));
    }
    progress.finish();

    EvaluationReport report;
    report.pixels = scored;
    report.skippedPixels = static_cast<std::size_t>(width) * height - scored;
    if (scored == 0) {
        throw InputError(modelPath, "no pixel has a valid fit: nothing to evaluate");
    }
    double pooled = 0;
    double psnrSum = 0;
    for (int s = 0; s < imageCount; ++s) {
        ImageScore score;
        score.name = capture.images[static_cast<std::size_t>(s)].file.filename().string();
        score.mse = squaredError[static_cast<std::size_t>(s)] / (3.0 * static_cast<double>(scored));
        score.rms = std::sqrt(score.mse) * 255.0;
        score.psnr = psnrFromMse(score.mse);
        pooled += score.mse;
        psnrSum += score.psnr;
        report.images.push_back(score);
    }
    pooled /= imageCount;
    report.rms = std::sqrt(pooled) * 255.0;
    report.psnr = psnrSum / imageCount;
    report.psnrPooled = psnrFromMse(pooled);
    if (options.predictionsDir) {
        for (int s = 0; s < imageCount; ++s) {
            const std::filesystem::path name =
                capture.images[static_cast<std::size_t>(s)].file.stem().string() + ".png";
            writeImage8(*options.predictionsDir / name, width, height, 3,
                        predictions[static_cast<std::size_t>(s)]);
        }
    }
    return report;
}

}  // namespace vpe
