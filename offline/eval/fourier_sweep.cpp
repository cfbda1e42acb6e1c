// SPDX-License-Identifier: MIT
// The M × λ sweep of the paper's Fig. 6.
#include "vpe/eval/fourier_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/eval/model_evaluation.h"
#include "vpe/fit/chunk_setup.h"
#include "vpe/normals/normal_source.h"
#include "vpe/plot/svg_line_plot.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/srgb.h"

namespace vpe::eval {

namespace {

// Squared-error sums per (λ, M, test image), merged from the threads.
struct ErrorTable {
    int lambdas, harmonics, images;
    std::vector<double> squared;
    std::vector<double> validLanes;  // [λ][M]
    ErrorTable(int l, int m, int i)
        : lambdas(l),
          harmonics(m),
          images(i),
          squared(static_cast<std::size_t>(l) * m * i, 0.0),
          validLanes(static_cast<std::size_t>(l) * m, 0.0) {}
    double& at(int l, int m, int i) {
        return squared[(static_cast<std::size_t>(l) * harmonics + m) * images + i];
    }
    double at(int l, int m, int i) const {
        return squared[(static_cast<std::size_t>(l) * harmonics + m) * images + i];
    }
    void add(const ErrorTable& other) {
        for (std::size_t i = 0; i < squared.size(); ++i) {
            squared[i] += other.squared[i];
        }
        for (std::size_t i = 0; i < validLanes.size(); ++i) {
            validLanes[i] += other.validLanes[i];
        }
    }
};

// What every chunk of the sweep reads.
struct SweepInputs {
    const capture::Capture& test;
    const capture::SurfaceGeometry& trainGeometry;
    const capture::SurfaceGeometry& testGeometry;
    const normals::NormalMap& normals;
    const fit::KernelLightSet& trainSet;
    const SweepOptions& options;
    int width;
    int testCount;
};

// The chunk's per-thread working memory.
struct ChunkScratch {
    std::unique_ptr<fit::NormalEquationSums> sums = std::make_unique<fit::NormalEquationSums>();
    std::unique_ptr<fit::ChunkSolution> solution = std::make_unique<fit::ChunkSolution>();
    fit::ChunkGeometry chunk;
    // Per lane and test light, [lane · testCount + s]: the angles and irradiance.
    std::vector<proto::ReflectionAngles<double>> angles;
    std::vector<double> irradiance;
};

// The test lights' angles and irradiance at each valid lane of the chunk at (x0, y); returns
// the chunk's lane count (short at the right edge).
int testLightGeometry(const SweepInputs& in, int x0, int y, const bool* laneValid,
                      ChunkScratch& scratch) {
    scratch.angles.assign(static_cast<std::size_t>(fit::kLanes * in.testCount), {});
    scratch.irradiance.assign(scratch.angles.size(), 1.0);
    int lanes = 0;
    for (int lane = 0; lane < fit::kLanes && x0 + lane < in.width; ++lane) {
        lanes = lane + 1;
        if (!laneValid[lane]) {
            continue;
        }
        const int x = x0 + lane;
        const proto::Vec3d n = in.normals.at(x, y);
        const proto::Vec3d v = in.testGeometry.toViewer(x, y);
        const proto::Vec3d p = in.testGeometry.position(x, y);
        for (int s = 0; s < in.testCount; ++s) {
            const capture::IncidentLight light =
                capture::incidentLight(in.test, in.test.images[static_cast<std::size_t>(s)], p);
            const std::size_t at = static_cast<std::size_t>(lane * in.testCount + s);
            scratch.angles[at] = proto::reflectionAngles(n, light.direction, v);
            scratch.irradiance[at] = light.irradiance;
        }
    }
    return lanes;
}

// Fits the chunk at band row r, column x0 for every (M, λ) and adds its held-out squared
// errors (8-bit sRGB) to `table`; returns the pixels it scored.
std::size_t scoreChunk(const SweepInputs& in, const capture::SampleBand& trainBand,
                       const capture::SampleBand& testBand, int rowBegin, int r, int x0,
                       ChunkScratch& scratch, ErrorTable& table) {
    const int y = rowBegin + r;
    bool laneValid[fit::kLanes];
    fit::fillChunkGeometry(in.trainGeometry, in.normals, x0, y, scratch.chunk, laneValid);
    // A research figure: always the exact accumulation (λ = 0 is in it).
    fit::accumulateNormalEquations(
        scratch.chunk, in.trainSet, fit::chunkObservations(trainBand, r, x0),
        in.options.maxHarmonics, fit::AccumulationPrecision::kDouble, *scratch.sums);
    const int lanes = testLightGeometry(in, x0, y, laneValid, scratch);
    const int lambdaCount = static_cast<int>(in.options.lambdas.size());
    const fit::ChunkSolution& solution = *scratch.solution;
    for (int m = 1; m <= in.options.maxHarmonics; ++m) {
        for (int l = 0; l < lambdaCount; ++l) {
            fit::solveNormalEquations(*scratch.sums, m,
                                      in.options.lambdas[static_cast<std::size_t>(l)],
                                      *scratch.solution);
            for (int lane = 0; lane < lanes; ++lane) {
                if (!laneValid[lane]) {
                    continue;
                }
                // An unsolvable system predicts black: the sweep shows what the fit would
                // deliver, failures included.
                table.validLanes[static_cast<std::size_t>(l) * in.options.maxHarmonics + m - 1] +=
                    solution.valid[lane] ? 1.0 : 0.0;
                for (int s = 0; s < in.testCount; ++s) {
                    const std::size_t at = static_cast<std::size_t>(lane * in.testCount + s);
                    double error = 0;
                    for (int c = 0; c < 3; ++c) {
                        const double predicted =
                            scratch.irradiance[at] *
                            proto::evaluateFourierBrdf(solution.coefficients[lane][c], m,
                                                       scratch.angles[at].cosThetaD,
                                                       scratch.angles[at].cosThetaS);
                        const double p8 = proto::linearToSrgb(std::clamp(predicted, 0.0, 1.0));
                        const double t8 = proto::linearToSrgb(std::clamp(
                            static_cast<double>(testBand.value(s, c, r, x0 + lane)), 0.0, 1.0));
                        error += (p8 - t8) * (p8 - t8);
                    }
                    table.at(l, m - 1, s) += error;
                }
            }
        }
    }
    std::size_t scored = 0;
    for (int lane = 0; lane < lanes; ++lane) {
        scored += laneValid[lane] ? 1 : 0;
    }
    return scored;
}

// The figures per (λ, M) from the pooled squared errors of `scored` pixels.
void summarize(const ErrorTable& total, std::size_t scored, SweepResult& result) {
    const int lambdaCount = total.lambdas, harmonicCount = total.harmonics;
    const int testCount = total.images;
    result.pixels = scored;
    for (int m = 1; m <= harmonicCount; ++m) {
        result.harmonics.push_back(m);
    }
    result.rms.assign(static_cast<std::size_t>(lambdaCount),
                      std::vector<double>(static_cast<std::size_t>(harmonicCount)));
    result.psnr = result.rms;
    result.validFraction = result.rms;
    for (int l = 0; l < lambdaCount; ++l) {
        for (int m = 0; m < harmonicCount; ++m) {
            double pooled = 0, psnrSum = 0;
            for (int s = 0; s < testCount; ++s) {
                const double mse = total.at(l, m, s) / (3.0 * static_cast<double>(scored));
                pooled += mse;
                psnrSum += psnrFromMse(mse);
            }
            const auto li = static_cast<std::size_t>(l);
            const auto mi = static_cast<std::size_t>(m);
            result.rms[li][mi] = std::sqrt(pooled / testCount) * 255.0;
            result.psnr[li][mi] = psnrSum / testCount;
            result.validFraction[li][mi] =
                total.validLanes[li * static_cast<std::size_t>(harmonicCount) + mi] /
                static_cast<double>(scored);
        }
    }
}

}  // namespace

SweepResult runSweep(const capture::Capture& train, const capture::Capture& test,
                     const SweepOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (options.maxHarmonics < 1 || options.maxHarmonics > proto::kMaxHarmonics) {
        throw common::InputError("--max-harmonics must be in 1.." +
                                 std::to_string(proto::kMaxHarmonics));
    }
    capture::ImageBandReader trainReader(train, options.threads);
    capture::ImageBandReader testReader(test, options.threads);
    const int width = trainReader.width();
    const int height = trainReader.height();
    if (testReader.width() != width || testReader.height() != height) {
        throw common::InputError(
            test.source, "images are " + std::to_string(testReader.width()) + "x" +
                             std::to_string(testReader.height()) + " but the training images are " +
                             std::to_string(width) + "x" + std::to_string(height));
    }
    normals::NormalsResult normals =
        normals::acquireNormals(train, options.normals, width, height, options.threads);
    const capture::SurfaceGeometry trainGeometry(train, width, height);
    const capture::SurfaceGeometry testGeometry(test, width, height);
    const std::vector<fit::KernelLight> trainLights = fit::kernelLights(train);
    const fit::KernelLightSet trainSet = fit::kernelLightSet(train, trainLights);
    const SweepInputs inputs{test,     trainGeometry, testGeometry, normals.normals,
                             trainSet, options,       width,        testReader.imageCount()};

    const int lambdaCount = static_cast<int>(options.lambdas.size());
    ErrorTable total(lambdaCount, options.maxHarmonics, inputs.testCount);
    std::size_t scored = 0;
    const int bandRows = std::min(trainReader.rowsForBudget(std::size_t{96} << 20),
                                  testReader.rowsForBudget(std::size_t{32} << 20));
    const int chunksPerRow = (width + fit::kLanes - 1) / fit::kLanes;
    capture::SampleBand trainBand, testBand;
    common::ProgressBar progress("sweep", static_cast<std::size_t>(height));
    for (int rowBegin = 0; rowBegin < height; rowBegin += bandRows) {
        const int rows = std::min(bandRows, height - rowBegin);
        trainReader.readBand(rowBegin, rows, nullptr, trainBand);
        testReader.readBand(rowBegin, rows, nullptr, testBand);
        // A table a row, added up in row order after the band: the sums do not depend on which
        // thread finished first (parallel_for.h), so neither does the sweep.
        std::vector<ErrorTable> rowErrors(
            static_cast<std::size_t>(rows),
            ErrorTable(lambdaCount, options.maxHarmonics, inputs.testCount));
        std::vector<std::size_t> rowScored(static_cast<std::size_t>(rows), 0);
        common::parallelFor(static_cast<std::size_t>(rows), 1, options.threads,
                            [&](std::size_t begin, std::size_t end) {
                                ChunkScratch scratch;
                                for (std::size_t row = begin; row < end; ++row) {
                                    for (int chunk = 0; chunk < chunksPerRow; ++chunk) {
                                        rowScored[row] +=
                                            scoreChunk(inputs, trainBand, testBand, rowBegin,
                                                       static_cast<int>(row), chunk * fit::kLanes,
                                                       scratch, rowErrors[row]);
                                    }
                                }
                            });
        for (int row = 0; row < rows; ++row) {
            total.add(rowErrors[static_cast<std::size_t>(row)]);
            scored += rowScored[static_cast<std::size_t>(row)];
        }
        progress.advance(static_cast<std::size_t>(rows));
    }
    progress.finish();
    if (scored == 0) {
        throw common::InputError(train.source, "no pixel has a usable normal: nothing to sweep");
    }

    SweepResult result;
    result.lambdas = options.lambdas;
    result.trainImages = trainReader.imageCount();
    result.testImages = inputs.testCount;
    result.normalsSource = normals.source;
    summarize(total, scored, result);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

void writeSweepCsv(const std::filesystem::path& path, const SweepResult& result) {
    std::ostringstream csv;
    csv << "lambda,harmonics,rms_8bit,psnr_db,valid_fraction\n";
    for (std::size_t l = 0; l < result.lambdas.size(); ++l) {
        for (std::size_t m = 0; m < result.harmonics.size(); ++m) {
            char line[160];
            std::snprintf(line, sizeof line, "%g,%d,%.5f,%.4f,%.5f\n", result.lambdas[l],
                          result.harmonics[m], result.rms[l][m], result.psnr[l][m],
                          result.validFraction[l][m]);
            csv << line;
        }
    }
    proto::writeTextFileAtomically(path, csv.str());
}

void writeSweepPlot(const std::filesystem::path& path, const SweepResult& result) {
    // The paper's line styles: solid, dotted, dashed, dash-dot, dash-dot-dot.
    const char* const dashes[] = {"", "2,4", "8,5", "10,4,2,4", "10,4,2,4,2,4"};
    plot::SvgLinePlot plot("RMS error on held-out lights (paper Fig. 6)", "harmonics M",
                           "RMS error (8-bit sRGB levels)");
    double best = 1e300;
    for (std::size_t l = 0; l < result.lambdas.size(); ++l) {
        std::vector<double> x(result.harmonics.begin(), result.harmonics.end());
        char name[48];
        std::snprintf(name, sizeof name, "λ = %g", result.lambdas[l]);
        plot.addSeries(name, x, result.rms[l], dashes[l % 5]);
        for (double v : result.rms[l]) {
            best = std::min(best, v);
        }
    }
    // An unregularized fit can blow up by orders of magnitude; cap the axis so the
    // regularized curves stay readable (the CSV keeps the true values).
    plot.setYCap(best * 4);
    plot.write(path);
}

}  // namespace vpe::eval
