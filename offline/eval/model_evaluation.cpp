// SPDX-License-Identifier: MIT
// Held-out evaluation of a model.
#include "vpe/eval/model_evaluation.h"

#include <algorithm>
#include <cmath>

#include "vpe/capture/geometry_calibration.h"
#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/eval/capture_predictor.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"

namespace vpe::eval {

double psnrFromMse(double mse) {
    // A perfect prediction is capped at 100 dB rather than infinity, so JSON stays numeric.
    return mse > 1e-10 ? 10.0 * std::log10(1.0 / mse) : 100.0;
}

EvaluationReport evaluateModel(const std::filesystem::path& modelPath,
                               const capture::Capture& statedCapture,
                               const EvaluationOptions& options) {
    model::ModelReader model(modelPath, model::ModelKinds::kAny);
    const model::ModelInfo& info = model.info();
    // The images are decoded with the response the model was fitted under, if calibrated.
    const capture::Capture underModel =
        capture::applyAcceptedCalibration(statedCapture, info.calibration, info.width, info.height);
    capture::ImageBandReader reader(underModel, options.threads);
    if (reader.width() != info.width || reader.height() != info.height) {
        throw common::InputError(statedCapture.source,
                                 "images are " + std::to_string(reader.width()) + "x" +
                                     std::to_string(reader.height()) + " but the model " +
                                     modelPath.string() + " is " + std::to_string(info.width) +
                                     "x" + std::to_string(info.height));
    }
    const CapturePredictor predictor(info, underModel,
                                     capture::storedTransfer(underModel, reader.eightBitCodes()));
    const capture::Capture& capture = predictor.capture();
    // Prediction and truth are compared as people see them (sRGB or the calibrated response).
    const capture::TransferFunction metric = capture::metricTransfer(capture);
    const int width = info.width;
    const int height = info.height;
    const int imageCount = reader.imageCount();

    std::vector<std::vector<std::uint8_t>> predictions;
    if (options.predictionsDir) {
        predictions.assign(
            static_cast<std::size_t>(imageCount),
            std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3, 0));
    }
    std::vector<double> squaredError(static_cast<std::size_t>(imageCount), 0.0);
    std::size_t scored = 0;
    // Each row's squared errors in place, added up in row order after the band: the sums do
    // not depend on which thread finished first (parallel_for.h), so neither does the report.
    std::vector<double> rowError;
    std::vector<std::size_t> rowScored;

    const int bandRows = reader.rowsForBudget(std::size_t{128} << 20);
    capture::SampleBand band;
    model::ModelRows rows;
    common::ProgressBar progress("eval", static_cast<std::size_t>(height));
    for (int rowBegin = 0; rowBegin < height; rowBegin += bandRows) {
        const int bandHeight = std::min(bandRows, height - rowBegin);
        reader.readBand(rowBegin, bandHeight, nullptr, band);
        model.readRows(rowBegin, bandHeight, rows);
        rowError.assign(static_cast<std::size_t>(bandHeight) * imageCount, 0.0);
        rowScored.assign(static_cast<std::size_t>(bandHeight), 0);
        common::parallelFor(
            static_cast<std::size_t>(bandHeight), 1, options.threads,
            [&](std::size_t begin, std::size_t end) {
                double* error = nullptr;
                auto score = [&](int s, int y, int x, int c, double p8, double t8) {
                    error[s] += (p8 - t8) * (p8 - t8);
                    if (!predictions.empty()) {
                        predictions[static_cast<std::size_t>(s)]
                                   [(static_cast<std::size_t>(y) * width + x) * 3 + c] =
                                       static_cast<std::uint8_t>(std::lround(p8 * 255));
                    }
                };
                for (std::size_t r = begin; r < end; ++r) {
                    const int row = static_cast<int>(r);
                    const int y = rowBegin + row;
                    error = rowError.data() + r * static_cast<std::size_t>(imageCount);
                    for (int x = 0; x < width; ++x) {
                        const std::size_t p = rows.pixel(row, x);
                        if (!rows.valid[p]) {
                            continue;
                        }
                        ++rowScored[r];
                        for (int s = 0; s < imageCount; ++s) {
                            const std::array<double, 3> predicted =
                                predictor.predict(rows, row, x, y, s);
                            for (int c = 0; c < 3; ++c) {
                                const double t8 = metric.encode(std::clamp(
                                    static_cast<double>(band.value(s, c, row, x)), 0.0, 1.0));
                                score(s, y, x, c, predicted[static_cast<std::size_t>(c)], t8);
                            }
                        }
                    }
                }
            });
        for (int row = 0; row < bandHeight; ++row) {
            for (int s = 0; s < imageCount; ++s) {
                squaredError[static_cast<std::size_t>(s)] +=
                    rowError[static_cast<std::size_t>(row) * imageCount + s];
            }
            scored += rowScored[static_cast<std::size_t>(row)];
        }
        progress.advance(static_cast<std::size_t>(bandHeight));
    }
    progress.finish();

    EvaluationReport report;
    report.pixels = scored;
    report.skippedPixels = static_cast<std::size_t>(width) * height - scored;
    if (scored == 0) {
        throw common::InputError(modelPath, "no pixel has a valid fit: nothing to evaluate");
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
            image::writeImage8(*options.predictionsDir / name, width, height, 3,
                               predictions[static_cast<std::size_t>(s)]);
        }
    }
    return report;
}

}  // namespace vpe::eval
