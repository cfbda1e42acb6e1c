// SPDX-License-Identifier: MIT
// Held-out selection of geometry and regularization.
#include "vpe/fit/held_out_search.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>

#include <Eigen/Dense>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/capture/transfer_function.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/seconds_since.h"
#include "vpe/fit/chunk_setup.h"
#include "vpe/model/light_transport.h"
#include "vpe/normals/photometric_stereo.h"

namespace vpe::fit {

// Every image's observations of a grid of pixels, in the kernel's lane layout: pixel p sits
// in chunk p / kLanes, lane p % kLanes.
struct HeldOutValidator::Samples {
    std::vector<int> x, y;
    int images = 0;
    bool eightBit = true;                 // the images hold 8-bit codes (their stored values' rule)
    std::vector<float> values;            // [chunk][image][channel][lane]
    std::vector<float> weights;           // [chunk][image][lane]
    std::vector<std::uint8_t> saturated;  // [chunk][image][lane]: a channel at full scale
    // The values' distinct numbers, and each value's index among them; both empty when there
    // are more than an index holds. 8-bit codes decode to at most 256 numbers, so what every
    // hypothesis computes from a value (its response's recoding, the metric's encoding, each a
    // pow() a value) is computed once per number and looked up: the same result, without the
    // pow() that was a tenth of an extended fit's time.
    std::vector<float> distinct;
    std::vector<std::uint16_t> distinctIndex;  // per value
    int chunks() const { return static_cast<int>((x.size() + fit::kLanes - 1) / fit::kLanes); }
    std::size_t valueIndex(int chunk, int image, int channel, int lane) const {
        return ((static_cast<std::size_t>(chunk) * images + image) * 3 + channel) * fit::kLanes +
               lane;
    }
    std::size_t weightIndex(int chunk, int image, int lane) const {
        return (static_cast<std::size_t>(chunk) * images + image) * fit::kLanes + lane;
    }
};

namespace {

// Fills samples.distinct and samples.distinctIndex (Samples) when the values hold few enough
// distinct numbers.
void indexDistinctValues(HeldOutValidator::Samples& samples) {
    std::vector<float> distinct = samples.values;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if (distinct.size() > std::numeric_limits<std::uint16_t>::max() ||
        std::any_of(distinct.begin(), distinct.end(), [](float v) { return std::isnan(v); })) {
        return;
    }
    samples.distinctIndex.resize(samples.values.size());
    for (std::size_t i = 0; i < samples.values.size(); ++i) {
        samples.distinctIndex[i] = static_cast<std::uint16_t>(
            std::lower_bound(distinct.begin(), distinct.end(), samples.values[i]) -
            distinct.begin());
    }
    samples.distinct = std::move(distinct);
}

// Calls take(x, y) for each pixel of the grid, row by row (heldOutGridPixels): a square
// lattice whose step leaves about `wanted` of `validCount` pixels, where valid(x, y).
template <typename Valid, typename Take>
void forEachGridPixel(int width, int height, double validCount, int wanted, Valid valid,
                      Take take) {
    // With at most about `wanted` normals (a map estimated on the grid alone) the step is 1
    // and the grid is every one of them.
    const int step = std::max(1, static_cast<int>(std::sqrt(validCount / std::max(wanted, 1))));
    for (int y = step / 2; y < height; y += step) {
        for (int x = step / 2; x < width; x += step) {
            if (valid(x, y)) {
                take(x, y);
            }
        }
    }
}

template <typename Take>
void forEachGridPixel(const normals::NormalMap& normals, int wanted, Take take) {
    std::size_t validCount = 0;
    for (std::uint8_t v : normals.valid) {
        validCount += v;
    }
    forEachGridPixel(
        normals.width, normals.height, static_cast<double>(validCount), wanted,
        [&](int x, int y) { return normals.validAt(x, y); }, take);
}

std::unique_ptr<HeldOutValidator::Samples> gatherSamples(const capture::Capture& capture,
                                                         const normals::NormalMap& normals,
                                                         int wanted, unsigned threads) {
    if (std::none_of(normals.valid.begin(), normals.valid.end(),
                     [](std::uint8_t v) { return v != 0; })) {
        throw common::InputError(capture.source,
                                 "no pixel has a normal: cannot calibrate geometry");
    }
    auto owned = std::make_unique<HeldOutValidator::Samples>();
    HeldOutValidator::Samples& samples = *owned;
    forEachGridPixel(normals, wanted, [&](int x, int y) {
        samples.x.push_back(x);
        samples.y.push_back(y);
    });
    capture::ImageBandReader reader(capture, threads);
    samples.images = reader.imageCount();
    samples.eightBit = reader.eightBitCodes();
    samples.values.assign(
        static_cast<std::size_t>(samples.chunks()) * samples.images * 3 * fit::kLanes, 0.0f);
    samples.weights.assign(
        static_cast<std::size_t>(samples.chunks()) * samples.images * fit::kLanes, 0.0f);
    samples.saturated.assign(samples.weights.size(), 0);
    const int bandRows = reader.rowsForBudget(std::size_t{96} << 20);
    capture::SampleBand band;
    std::size_t next = 0;  // samples are in row order
    for (int rowBegin = 0; rowBegin < reader.height(); rowBegin += bandRows) {
        const int rows = std::min(bandRows, reader.height() - rowBegin);
        reader.readBand(rowBegin, rows, nullptr, band);
        for (; next < samples.x.size() && samples.y[next] < rowBegin + rows; ++next) {
            const int chunk = static_cast<int>(next / fit::kLanes);
            const int lane = static_cast<int>(next % fit::kLanes);
            const int r = samples.y[next] - rowBegin;
            for (int s = 0; s < samples.images; ++s) {
                for (int c = 0; c < 3; ++c) {
                    samples.values[samples.valueIndex(chunk, s, c, lane)] =
                        band.value(s, c, r, samples.x[next]);
                }
                samples.weights[samples.weightIndex(chunk, s, lane)] =
                    band.weight(s, r, samples.x[next]);
                samples.saturated[samples.weightIndex(chunk, s, lane)] =
                    band.isSaturated(s, r, samples.x[next]) ? 1 : 0;
            }
        }
    }
    indexDistinctValues(samples);
    return owned;
}

}  // namespace

HeldOutValidator::HeldOutValidator(const capture::Capture& capture,
                                   const normals::NormalMap& normals, int samplePixels,
                                   int holdOutEvery, unsigned threads)
    : capture_(capture),
      normals_(normals),
      holdOutEvery_(holdOutEvery),
      threads_(threads),
      samples_(gatherSamples(capture, normals, samplePixels, threads)) {}

HeldOutValidator::~HeldOutValidator() = default;

namespace {

// What a hypothesis changes: the rig's geometry and the camera's response, and so the values
// the stored codes decode to. Predictions are compared with the stored values as people see
// them: the capture's sRGB, or the response under test, whose images are the same codes
// decoded another way.
struct Hypothesis {
    capture::Capture calibrated;
    capture::SurfaceGeometry geometry;
    capture::TransferFunction metric;
    std::vector<fit::KernelLight> lights;
    fit::KernelLightSet lightSet;
    std::vector<float> recoded;  // empty: the samples' own values
    const std::vector<float>* values;
    // The metric's encoding of each of the samples' distinct numbers as this hypothesis decodes
    // them (Samples::distinct; empty with it).
    std::vector<double> encodedDistinct;

    Hypothesis(const capture::Capture& capture, const HeldOutValidator::Samples& samples,
               const capture::GeometryCalibration& calibration, int width, int height)
        : calibrated(capture::applyGeometryCalibration(capture, calibration, width, height)),
          geometry(calibrated, width, height),
          metric(capture::metricTransfer(calibrated)),
          lights(fit::kernelLights(calibrated)),
          lightSet(fit::kernelLightSet(calibrated, lights)),
          values(&samples.values) {
        const bool recode =
            calibrated.encoding != capture.encoding || calibrated.gamma != capture.gamma;
        const capture::TransferFunction stated = capture::storedTransfer(capture, true);
        const capture::TransferFunction response = capture::storedTransfer(calibrated, true);
        const auto recodedValue = [&](float value) {
            return static_cast<float>(response.decode(stated.encode(static_cast<double>(value))));
        };
        std::vector<float> recodedDistinct(samples.distinct.size());
        encodedDistinct.resize(samples.distinct.size());
        for (std::size_t d = 0; d < samples.distinct.size(); ++d) {
            recodedDistinct[d] = recode ? recodedValue(samples.distinct[d]) : samples.distinct[d];
            encodedDistinct[d] =
                metric.encode(std::clamp(static_cast<double>(recodedDistinct[d]), 0.0, 1.0));
        }
        if (recode) {
            recoded.resize(samples.values.size());
            for (std::size_t i = 0; i < recoded.size(); ++i) {
                recoded[i] = samples.distinctIndex.empty()
                                 ? recodedValue(samples.values[i])
                                 : recodedDistinct[samples.distinctIndex[i]];
            }
            values = &recoded;
        }
    }
    // The metric's encoding of sample i's value, clamped to [0, 1].
    double encodedObserved(const HeldOutValidator::Samples& samples, std::size_t i) const {
        return samples.distinctIndex.empty()
                   ? metric.encode(std::clamp(static_cast<double>((*values)[i]), 0.0, 1.0))
                   : encodedDistinct[samples.distinctIndex[i]];
    }
    Hypothesis(const Hypothesis&) = delete;  // lightSet points into lights
    Hypothesis& operator=(const Hypothesis&) = delete;
};

// One fitted pixel of the grid: its predictions of the samples, in the hypothesis' linear
// values. `transport` is the extended model's T of the pixel (kTransportValues), or null
// (T ≡ 1).
class FittedPixel {
public:
    FittedPixel(const HeldOutValidator::Samples& samples, const Hypothesis& hypothesis, int chunk,
                int lane, const proto::Vec3d& normal,
                const float (&coefficients)[3][fit::kMaxCoefficients], int harmonics,
                const float* transport)
        : hypothesis_(hypothesis),
          normal_(normal),
          coefficients_(coefficients),
          harmonics_(harmonics),
          transport_(transport) {
        const std::size_t p = static_cast<std::size_t>(chunk) * fit::kLanes + lane;
        toViewer_ = hypothesis.geometry.toViewer(samples.x[p], samples.y[p]);
        position_ = hypothesis.geometry.position(samples.x[p], samples.y[p]);
    }

    // The prediction of image s, channel by channel.
    std::array<double, 3> predict(int s) const {
        const capture::CaptureImage& image =
            hypothesis_.calibrated.images[static_cast<std::size_t>(s)];
        const capture::IncidentLight light =
            capture::incidentLight(hypothesis_.calibrated, image, position_);
        const auto angles = proto::reflectionAngles(normal_, light.direction, toViewer_);
        const std::array<double, model::kTransportChannels> t =
            transport_ ? model::evaluateColourTransport(
                             transport_, model::transportDirection(hypothesis_.calibrated, image))
                       : std::array<double, model::kTransportChannels>{1.0, 1.0, 1.0};
        double f[3];  // one harmonic recurrence for the three channels
        proto::evaluateFourierBrdfRgb(&coefficients_[0][0], fit::kMaxCoefficients, harmonics_,
                                      angles.cosThetaD, angles.cosThetaS, f);
        std::array<double, 3> rgb;
        for (int k = 0; k < 3; ++k) {
            rgb[static_cast<std::size_t>(k)] =
                t[static_cast<std::size_t>(k)] * light.irradiance * f[k];
        }
        return rgb;
    }

private:
    const Hypothesis& hypothesis_;
    proto::Vec3d normal_;
    const float (&coefficients_)[3][fit::kMaxCoefficients];
    int harmonics_;
    const float* transport_;
    proto::Vec3d toViewer_, position_;
};

// Squared errors, in the metric's full-scale units, of fitted pixels' predictions at the
// held-out lights, per image.
struct HeldOutErrors {
    std::vector<double> imageSquared, imageCount;

    explicit HeldOutErrors(int images)
        : imageSquared(static_cast<std::size_t>(images), 0.0),
          imageCount(static_cast<std::size_t>(images), 0.0) {}

    // The pixel's predictions of the lights at positions fold, fold + holdOutEvery, ….
    void add(const HeldOutValidator::Samples& samples, const Hypothesis& hypothesis,
             int holdOutEvery, int fold, int chunk, int lane, const FittedPixel& pixel) {
        for (int s = fold; s < samples.images; s += holdOutEvery) {
            if (samples.weights[samples.weightIndex(chunk, s, lane)] <= 0) {
                continue;
            }
            const std::array<double, 3> predicted = pixel.predict(s);
            for (int k = 0; k < 3; ++k) {
                const double e =
                    hypothesis.metric.encode(
                        std::clamp(predicted[static_cast<std::size_t>(k)], 0.0, 1.0)) -
                    hypothesis.encodedObserved(samples, samples.valueIndex(chunk, s, k, lane));
                imageSquared[static_cast<std::size_t>(s)] += e * e;
                imageCount[static_cast<std::size_t>(s)] += 1;
            }
        }
    }
    void merge(const HeldOutErrors& other) {
        for (std::size_t s = 0; s < imageSquared.size(); ++s) {
            imageSquared[s] += other.imageSquared[s];
            imageCount[s] += other.imageCount[s];
        }
    }
    // Pooled over the held-out samples, in 8-bit levels.
    double rms() const {
        double squared = 0, count = 0;
        for (std::size_t s = 0; s < imageSquared.size(); ++s) {
            squared += imageSquared[s];
            count += imageCount[s];
        }
        return count > 0 ? std::sqrt(squared / count) * 255.0 : 1e9;
    }
    // The geometric mean of the held-out images' RMS, in 8-bit levels: the RMS whose PSNR is
    // the mean of the images' PSNR, vpe eval's headline figure. Pooling lets the bright
    // images outweigh the dark ones; this does not.
    double imageMeanRms() const {
        double logSum = 0;
        int images = 0;
        for (std::size_t s = 0; s < imageSquared.size(); ++s) {
            if (imageCount[s] > 0) {
                logSum += std::log(std::sqrt(imageSquared[s] / imageCount[s]) * 255.0 + 1e-9);
                ++images;
            }
        }
        return images > 0 ? std::exp(logSum / images) : 1e9;
    }
};

// Per light: Σ w ŷ y and Σ w ŷ² of fitted pixels over their training samples and channels.
struct LightGainSums {
    std::vector<double> cross, square;

    explicit LightGainSums(int images)
        : cross(static_cast<std::size_t>(images), 0.0),
          square(static_cast<std::size_t>(images), 0.0) {}

    void add(const HeldOutValidator::Samples& samples, const Hypothesis& hypothesis,
             const capture::SampleBand& training, int chunk, int lane, const FittedPixel& pixel) {
        for (int s = 0; s < samples.images; ++s) {
            const std::size_t w = samples.weightIndex(chunk, s, lane);
            if (training.weights[w] <= 0 || samples.saturated[w]) {
                continue;
            }
            const std::array<double, 3> predicted = pixel.predict(s);
            const double weight = training.weights[w];
            for (int k = 0; k < 3; ++k) {
                const double y = (*hypothesis.values)[samples.valueIndex(chunk, s, k, lane)];
                const double p = predicted[static_cast<std::size_t>(k)];
                cross[static_cast<std::size_t>(s)] += weight * p * y;
                square[static_cast<std::size_t>(s)] += weight * p * p;
            }
        }
    }
    void merge(const LightGainSums& other) {
        for (std::size_t s = 0; s < cross.size(); ++s) {
            cross[s] += other.cross[s];
            square[s] += other.square[s];
        }
    }
};

// The grid's geometry for one chunk of lanes.
void fillSampleChunk(const HeldOutValidator::Samples& samples,
                     const capture::SurfaceGeometry& geometry, const normals::NormalMap& normals,
                     int chunk, fit::ChunkGeometry& out, bool (&laneValid)[fit::kLanes]) {
    for (int lane = 0; lane < fit::kLanes; ++lane) {
        const std::size_t p = static_cast<std::size_t>(chunk) * fit::kLanes + lane;
        const bool present = p < samples.x.size();
        fit::fillChunkLane(geometry, normals, present ? samples.x[p] : -1,
                           present ? samples.y[p] : 0, lane, out, laneValid[lane]);
    }
}

proto::Vec3d laneNormal(const fit::ChunkGeometry& chunk, int lane) {
    return {chunk.normal[0][lane], chunk.normal[1][lane], chunk.normal[2][lane]};
}

// Runs makeWorker()'s callable (chunk, accumulator) over every chunk of the grid on the
// worker threads, each thread into its own copy of `empty`, and merges the copies.
template <typename Accumulator, typename MakeWorker>
Accumulator reduceEveryChunk(const HeldOutValidator::Samples& samples, unsigned threads,
                             const Accumulator& empty, MakeWorker makeWorker) {
    Accumulator total = empty;
    std::mutex mergeMutex;
    common::parallelFor(static_cast<std::size_t>(samples.chunks()), 4, threads,
                        [&](std::size_t begin, std::size_t end) {
                            auto worker = makeWorker();
                            Accumulator local = empty;
                            for (std::size_t c = begin; c < end; ++c) {
                                worker(static_cast<int>(c), local);
                            }
                            std::lock_guard lock(mergeMutex);
                            total.merge(local);
                        });
    return total;
}

}  // namespace

double HeldOutValidator::score(const capture::GeometryCalibration& calibration, int harmonics,
                               double lambda, HeldOutFolds folds) const {
    const Samples& samples = *samples_;
    const Hypothesis hypothesis(capture_, samples, calibration, normals_.width, normals_.height);
    const int firstFold = folds == HeldOutFolds::kEvery ? 0 : holdOutEvery_ - 1;
    const HeldOutErrors heldOut =
        reduceEveryChunk(samples, threads_, HeldOutErrors(samples.images), [&] {
            return [&, sums = std::make_unique<fit::NormalEquationSums>(),
                    solution = std::make_unique<fit::ChunkSolution>(),
                    weights =
                        std::vector<float>(static_cast<std::size_t>(samples.images) * fit::kLanes),
                    chunk = fit::ChunkGeometry{}](int c, HeldOutErrors& errors) mutable {
                bool laneValid[fit::kLanes];
                fillSampleChunk(samples, hypothesis.geometry, normals_, c, chunk, laneValid);
                for (int fold = firstFold; fold < holdOutEvery_; ++fold) {
                    for (int s = 0; s < samples.images; ++s) {
                        for (int lane = 0; lane < fit::kLanes; ++lane) {
                            weights[static_cast<std::size_t>(s) * fit::kLanes + lane] =
                                s % holdOutEvery_ == fold
                                    ? 0.0f
                                    : samples.weights[samples.weightIndex(c, s, lane)];
                        }
                    }
                    fit::ChunkObservations observations;
                    observations.values = &(*hypothesis.values)[samples.valueIndex(c, 0, 0, 0)];
                    observations.sampleStride = 3 * fit::kLanes;
                    observations.channelStride = fit::kLanes;
                    observations.weights = weights.data();
                    observations.weightStride = fit::kLanes;
                    fit::accumulateNormalEquations(chunk, hypothesis.lightSet, observations,
                                                   harmonics,
                                                   fit::AccumulationPrecision::kFloatBlocks, *sums);
                    fit::solveNormalEquations(*sums, harmonics, lambda, *solution);
                    for (int lane = 0; lane < fit::kLanes; ++lane) {
                        if (laneValid[lane] && solution->valid[lane]) {
                            errors.add(
                                samples, hypothesis, holdOutEvery_, fold, c, lane,
                                FittedPixel(samples, hypothesis, c, lane, laneNormal(chunk, lane),
                                            solution->coefficients[lane], harmonics, nullptr));
                        }
                    }
                }
            };
        });
    return heldOut.rms();
}

namespace {

// The grid as one row of a band (the same chunk layout), the lights of `fold` (positions fold,
// fold + holdOutEvery, …) unusable; fold < 0: every light usable.
capture::SampleBand gridBand(const HeldOutValidator::Samples& samples,
                             const std::vector<float>& values, int holdOutEvery, int fold) {
    capture::SampleBand band;
    band.resize(samples.images, static_cast<int>(samples.x.size()), 1);
    std::copy(values.begin(), values.end(), band.values.begin());
    for (int c = 0; c < samples.chunks(); ++c) {
        for (int s = 0; s < samples.images; ++s) {
            for (int lane = 0; lane < fit::kLanes; ++lane) {
                const std::size_t i = samples.weightIndex(c, s, lane);
                band.weights[i] = s % holdOutEvery == fold ? 0.0f : samples.weights[i];
                band.saturated[i] = samples.saturated[i];
            }
        }
    }
    return band;
}

// The extended fit of every chunk of the grid on `training`: add(accumulator, chunk, lane,
// pixel) takes each fitted pixel into its thread's accumulator, and the accumulators merge.
// With a normal search (settings.normalSearchDegrees), `refined` holds the normals of this
// training set and rig: found by this fit when not yet filled, else taken as they are.
template <typename Accumulator, typename Add>
Accumulator fitEveryChunkExtended(const HeldOutValidator::Samples& samples,
                                  const normals::NormalMap& normals, const Hypothesis& hypothesis,
                                  const capture::SampleBand& training,
                                  const fit::ExtendedFitSettings& settings, unsigned threads,
                                  HeldOutValidator::RefinedNormals& refined,
                                  const Accumulator& empty, Add add) {
    static_assert(fit::kLanes == capture::SampleBand::kChunkWidth,
                  "the grid's chunks are the band's");
    const fit::ExtendedLightTable table(hypothesis.calibrated);
    const bool search = settings.normalSearchDegrees > 0;
    const bool reuse = search && refined.filled;
    fit::ExtendedFitSettings fitSettings = settings;
    if (reuse) {
        fitSettings.normalSearchDegrees = 0;
    } else if (search) {
        refined.xyz.assign(samples.x.size() * 3, 0.0f);
    }
    Accumulator total = reduceEveryChunk(samples, threads, empty, [&] {
        return [&, solution = std::make_unique<fit::ExtendedChunkSolution>(),
                chunk = fit::ChunkGeometry{}](int c, Accumulator& accumulator) mutable {
            bool laneValid[fit::kLanes];
            fillSampleChunk(samples, hypothesis.geometry, normals, c, chunk, laneValid);
            const std::size_t first = static_cast<std::size_t>(c) * fit::kLanes;
            const int lanes =
                static_cast<int>(std::min<std::size_t>(fit::kLanes, samples.x.size() - first));
            if (reuse) {
                for (int lane = 0; lane < lanes; ++lane) {
                    for (int a = 0; a < 3; ++a) {
                        chunk.normal[a][lane] = refined.xyz[(first + lane) * 3 + a];
                    }
                }
            }
            fit::fitChunkExtendedRefiningNormals(hypothesis.calibrated, table, chunk, laneValid,
                                                 hypothesis.lightSet, training, 0, c * fit::kLanes,
                                                 fitSettings, *solution);
            if (search && !reuse) {
                for (int lane = 0; lane < lanes; ++lane) {
                    for (int a = 0; a < 3; ++a) {
                        refined.xyz[(first + lane) * 3 + a] = chunk.normal[a][lane];
                    }
                }
            }
            for (int lane = 0; lane < fit::kLanes; ++lane) {
                if (laneValid[lane] && solution->brdf.valid[lane]) {
                    add(accumulator, c, lane,
                        FittedPixel(samples, hypothesis, c, lane, laneNormal(chunk, lane),
                                    solution->brdf.coefficients[lane], settings.harmonics,
                                    solution->transport[lane]));
                }
            }
        };
    });
    refined.filled = refined.filled || search;
    return total;
}

// The errors at the lights of `fold` of the extended fit on the grid's other lights.
HeldOutErrors transportFoldErrors(const HeldOutValidator::Samples& samples,
                                  const normals::NormalMap& normals, const Hypothesis& hypothesis,
                                  const fit::ExtendedFitSettings& settings, unsigned threads,
                                  int holdOutEvery, int fold,
                                  HeldOutValidator::RefinedNormals& refined) {
    return fitEveryChunkExtended(
        samples, normals, hypothesis, gridBand(samples, *hypothesis.values, holdOutEvery, fold),
        settings, threads, refined, HeldOutErrors(samples.images),
        [&](HeldOutErrors& errors, int chunk, int lane, const FittedPixel& pixel) {
            errors.add(samples, hypothesis, holdOutEvery, fold, chunk, lane, pixel);
        });
}

}  // namespace

// The normal search is most of an extended fit's time (12 tilts, each a T and an f fit), and
// the blocked-light stage fits the grid some eighteen times (the tables of every light and of
// every fold, each in two rounds, and their scores). The normals are the surface's, and a
// light's intensity barely moves them: each training set's are refined once, by its first
// fit, and kept for the tables after it. The rig (field of view, light distance, response)
// changes every light's direction at a texel, and T's ridge decides how much of a tilt's
// shading T may take up, so each has normals of its own: judged under the normals of the
// first ridge tried, realrti-dev item3 chose T's ridge 1 where its own normals chose 0.3,
// and lost 0.27 dB on its test lights.
HeldOutValidator::RefinedNormals& HeldOutValidator::refinedNormals(
    const capture::GeometryCalibration& calibration, double transportRidge, int heldOutFold) const {
    for (const std::unique_ptr<RefinedNormals>& known : refinedNormals_) {
        if (known->heldOutFold == heldOutFold && known->transportRidge == transportRidge &&
            known->rig.fieldOfViewDegrees == calibration.fieldOfViewDegrees &&
            known->rig.lightDistance == calibration.lightDistance &&
            known->rig.responseGamma == calibration.responseGamma) {
            return *known;
        }
    }
    auto entry = std::make_unique<RefinedNormals>();
    entry->heldOutFold = heldOutFold;
    entry->rig = {
        calibration.fieldOfViewDegrees, calibration.lightDistance, calibration.responseGamma, {}};
    entry->transportRidge = transportRidge;
    refinedNormals_.push_back(std::move(entry));
    return *refinedNormals_.back();
}

HeldOutScore HeldOutValidator::scoreWithTransport(const capture::GeometryCalibration& calibration,
                                                  const fit::ExtendedFitSettings& settings,
                                                  HeldOutFolds folds) const {
    const Samples& samples = *samples_;
    const Hypothesis hypothesis(capture_, samples, calibration, normals_.width, normals_.height);
    // One fold, as for everything else the search chooses: judged over all four folds in
    // turn, realrti-dev item5 chose 0.01 and lost 1.9 dB on its test lights.
    HeldOutErrors heldOut(samples.images);
    for (int fold = folds == HeldOutFolds::kEvery ? 0 : holdOutEvery_ - 1; fold < holdOutEvery_;
         ++fold) {
        heldOut.merge(
            transportFoldErrors(samples, normals_, hypothesis, settings, threads_, holdOutEvery_,
                                fold, refinedNormals(calibration, settings.transportRidge, fold)));
    }
    return {heldOut.rms(), heldOut.imageMeanRms()};
}

HeldOutScore HeldOutValidator::scoreWithTransportByFold(
    const std::vector<capture::GeometryCalibration>& byFold,
    const fit::ExtendedFitSettings& settings) const {
    const Samples& samples = *samples_;
    HeldOutErrors heldOut(samples.images);
    for (int fold = 0; fold < holdOutEvery_; ++fold) {
        const Hypothesis hypothesis(capture_, samples, byFold.at(static_cast<std::size_t>(fold)),
                                    normals_.width, normals_.height);
        heldOut.merge(transportFoldErrors(samples, normals_, hypothesis, settings, threads_,
                                          holdOutEvery_, fold,
                                          refinedNormals(byFold.at(static_cast<std::size_t>(fold)),
                                                         settings.transportRidge, fold)));
    }
    return {heldOut.rms(), heldOut.imageMeanRms()};
}

HeldOutScore HeldOutValidator::scoreRtiBasis(const model::RtiBasis& basis,
                                             HeldOutFolds folds) const {
    const Samples& samples = *samples_;
    const capture::TransferFunction stored = capture::storedTransfer(capture_, samples.eightBit);
    const capture::TransferFunction metric = capture::metricTransfer(capture_);
    Eigen::MatrixXd design(samples.images, basis.terms);
    std::vector<double> row(static_cast<std::size_t>(basis.terms));
    for (int s = 0; s < samples.images; ++s) {
        basis.evaluate(capture_.images[static_cast<std::size_t>(s)].light, row.data());
        for (int k = 0; k < basis.terms; ++k) {
            design(s, k) = row[static_cast<std::size_t>(k)];
        }
    }
    HeldOutErrors heldOut(samples.images);
    for (int fold = folds == HeldOutFolds::kEvery ? 0 : holdOutEvery_ - 1; fold < holdOutEvery_;
         ++fold) {
        heldOut.merge(reduceEveryChunk(samples, threads_, HeldOutErrors(samples.images), [&] {
            return [&](int c, HeldOutErrors& errors) {
                Eigen::VectorXd weights(samples.images);
                Eigen::MatrixXd values(samples.images, 3);
                for (int lane = 0; lane < fit::kLanes; ++lane) {
                    const std::size_t p = static_cast<std::size_t>(c) * fit::kLanes + lane;
                    if (p >= samples.x.size()) {
                        break;
                    }
                    int usable = 0;
                    for (int s = 0; s < samples.images; ++s) {
                        const bool train = s % holdOutEvery_ != fold &&
                                           samples.weights[samples.weightIndex(c, s, lane)] > 0;
                        weights(s) = train ? 1.0 : 0.0;
                        usable += train ? 1 : 0;
                        for (int k = 0; k < 3; ++k) {
                            values(s, k) = stored.encode(static_cast<double>(
                                samples.values[samples.valueIndex(c, s, k, lane)]));
                        }
                    }
                    if (usable < basis.terms) {
                        continue;
                    }
                    const Eigen::MatrixXd coefficients = (weights.asDiagonal() * design)
                                                             .completeOrthogonalDecomposition()
                                                             .solve(weights.asDiagonal() * values);
                    const Eigen::MatrixXd predicted = design * coefficients;
                    for (int s = fold; s < samples.images; s += holdOutEvery_) {
                        if (samples.weights[samples.weightIndex(c, s, lane)] <= 0) {
                            continue;
                        }
                        for (int k = 0; k < 3; ++k) {
                            // In the metric's values, as the Fourier hypotheses are scored.
                            const double e =
                                metric.encode(
                                    stored.decode(std::clamp(predicted(s, k), 0.0, 1.0))) -
                                metric.encode(std::clamp(
                                    static_cast<double>(
                                        samples.values[samples.valueIndex(c, s, k, lane)]),
                                    0.0, 1.0));
                            errors.imageSquared[static_cast<std::size_t>(s)] += e * e;
                            errors.imageCount[static_cast<std::size_t>(s)] += 1;
                        }
                    }
                }
            };
        }));
    }
    return {heldOut.rms(), heldOut.imageMeanRms()};
}

std::vector<double> HeldOutValidator::lightGains(const capture::GeometryCalibration& calibration,
                                                 const fit::ExtendedFitSettings& settings,
                                                 int heldOutFold) const {
    const Samples& samples = *samples_;
    const Hypothesis hypothesis(capture_, samples, calibration, normals_.width, normals_.height);
    const capture::SampleBand training =
        gridBand(samples, *hypothesis.values, holdOutEvery_, heldOutFold);
    const LightGainSums sums = fitEveryChunkExtended(
        samples, normals_, hypothesis, training, settings, threads_,
        refinedNormals(calibration, settings.transportRidge, heldOutFold),
        LightGainSums(samples.images),
        [&](LightGainSums& gains, int chunk, int lane, const FittedPixel& pixel) {
            gains.add(samples, hypothesis, training, chunk, lane, pixel);
        });
    std::vector<double> gains(sums.cross.size(), 0.0);
    for (std::size_t s = 0; s < gains.size(); ++s) {
        gains[s] = sums.square[s] > 0 ? sums.cross[s] / sums.square[s] : 0.0;
    }
    return gains;
}

namespace {

// `calibration` with the intensities of the lights the fit uses (all when heldOutFold < 0,
// else those outside that fold) estimated from the grid. The fit and the gains alternate: T and the
// BRDF first explain what they can, and what stays common to every pixel under one light is that
// light's. The median light keeps intensity 1, so the BRDF keeps its units.
// Only blocked lights, below kBlockedBelow of the median, keep their own intensity; the
// others count as 1. The lamps' own differences (±5% on realrti-dev's domes) are real for
// the lights measured, but say nothing about a light between them: interpolated into the
// held-out lights they cost more than they gained (item7's search fold: per-image RMS 3.84
// keeping every light's own intensity, 3.67 / 3.64 / 3.66 blocking below 95% / 90% / 80%,
// 3.71 as stated). A blocked light's neighbour on its ring is likely blocked too.
// The gains are measured under a grey T. An intensity is the light's luminance; T's colour
// traded a blocked ring's darkness against tint (item7: the lights beside the ring fell to
// 0.76–0.85 of the model, and the fold rejected the table).
capture::GeometryCalibration calibrateLightIntensities(const HeldOutValidator& validator,
                                                       const capture::Capture& capture,
                                                       capture::GeometryCalibration calibration,
                                                       const fit::ExtendedFitSettings& settings,
                                                       int holdOutEvery, int heldOutFold) {
    constexpr int kRounds = 2;
    constexpr double kLowest = 1e-3;  // a light that shows nothing keeps a little
    constexpr double kBlockedBelow = 0.9;
    std::vector<double> intensity(capture.images.size(), 1.0);
    auto table = [&] {
        std::vector<capture::LightIntensity> entries;
        for (std::size_t s = 0; s < capture.images.size(); ++s) {
            if (static_cast<int>(s) % holdOutEvery != heldOutFold) {
                entries.push_back({proto::normalized(capture.images[s].light), intensity[s]});
            }
        }
        return entries;
    };
    fit::ExtendedFitSettings greySettings = settings;
    greySettings.colourTransport = false;
    for (int round = 0; round < kRounds; ++round) {
        calibration.lightIntensities = table();
        const std::vector<double> gains =
            validator.lightGains(calibration, greySettings, heldOutFold);
        std::vector<double> used;
        for (std::size_t s = 0; s < intensity.size(); ++s) {
            if (gains[s] > 0) {
                intensity[s] = std::max(kLowest, intensity[s] * gains[s]);
                used.push_back(intensity[s]);
            }
        }
        if (used.empty()) {
            break;
        }
        std::nth_element(used.begin(), used.begin() + static_cast<long>(used.size() / 2),
                         used.end());
        const double median = used[used.size() / 2];
        for (std::size_t s = 0; s < intensity.size(); ++s) {
            const double relative = intensity[s] / median;
            intensity[s] = gains[s] > 0 && relative < kBlockedBelow ? relative : 1.0;
        }
    }
    calibration.lightIntensities = table();
    return calibration;
}

// The held-out search's stages (docs/extended-model.md, "How it is fitted", step 1), in the
// order run() takes them: the camera response, the rig's geometry, the regularization, the
// stated geometry's score, T's ridge and the blocked lights. Every stage scores hypotheses
// into one result, which keeps the best so far.
class HeldOutSearch {
public:
    HeldOutSearch(const capture::Capture& capture, const normals::NormalMap& normals,
                  const HeldOutSearchOptions& options);
    HeldOutSearchResult run();

private:
    double score(const capture::GeometryCalibration& calibration, int harmonics, double lambda);
    void judgeBy(HeldOutFolds next);
    void refineGeometry(int rounds);
    int trainingLights() const;
    void searchResponse();
    void searchGeometry();
    void searchRegularization();
    void scoreStatedGeometry();
    fit::ExtendedFitSettings extendedSettings() const;
    void searchTransportRidge();
    void searchLightIntensities();
    void compareClassicBases();

    const capture::Capture& capture_;
    const HeldOutSearchOptions& options_;
    const HeldOutValidator validator_;
    HeldOutSearchResult result_;
    // The camera and the rig (response, field of view, light distance) are the same under
    // every light, so every training light judges them, each fold fitted on the other three:
    // on realrti-dev item7 one fold's choice moved with the fold (γ 1.7 and 13.75°, or sRGB,
    // or 50° with a misfired exposure in the fold), and every fold's held γ 1.4 on all three
    // rotations of the protocol, +0.3 dB on each. How far the model may be trusted between and
    // beyond the lights (M, λ, T's ridge) stays judged on the one fold: chosen on every fold,
    // item5 (whose test lights lie below all its training lights) took M = 6, λ = 0.03 and
    // lost 3 dB. The blocked lights are judged on every fold (searchLightIntensities).
    HeldOutFolds folds_;
    // The extended fit as chosen over every fold, when the blocked-light stage scored it.
    std::optional<HeldOutScore> everyFold_;
};

HeldOutSearch::HeldOutSearch(const capture::Capture& capture, const normals::NormalMap& normals,
                             const HeldOutSearchOptions& options)
    : capture_(capture),
      options_(options),
      validator_(capture, normals, options.samplePixels, options.holdOutEvery, options.threads),
      folds_(options.calibrateResponse || options.calibrateGeometry ? HeldOutFolds::kEvery
                                                                    : HeldOutFolds::kOne) {
    result_.harmonics = options.harmonics;
    result_.lambda = options.lambda;
}

HeldOutSearchResult HeldOutSearch::run() {
    const auto timed = [this](const char* stage, auto&& run) {
        const auto start = std::chrono::steady_clock::now();
        run();
        result_.stageSeconds.push_back({stage, common::secondsSince(start)});
    };
    timed("stated",
          [&] { score(capture::GeometryCalibration{}, options_.harmonics, options_.lambda); });
    if (options_.calibrateResponse) {
        timed("response", [&] { searchResponse(); });
    }
    if (options_.calibrateGeometry) {
        timed("geometry", [&] { searchGeometry(); });
    }
    if (options_.selectRegularization) {
        timed("regularization", [&] { searchRegularization(); });
    }
    timed("stated geometry", [&] { scoreStatedGeometry(); });
    if (options_.selectTransportRidge) {
        timed("transport ridge", [&] { searchTransportRidge(); });
        if (options_.calibrateLightIntensities) {
            timed("blocked lights", [&] { searchLightIntensities(); });
        }
        if (options_.compareClassicBases) {
            timed("classic bases", [&] { compareClassicBases(); });
        }
    }
    return result_;
}

// The held-out RMS of one hypothesis over the current folds (a hypothesis scored before is
// not fitted again); the result takes it when it is the best so far.
double HeldOutSearch::score(const capture::GeometryCalibration& calibration, int harmonics,
                            double lambda) {
    for (const HeldOutTrial& known : result_.trials) {
        if (known.calibration.fieldOfViewDegrees == calibration.fieldOfViewDegrees &&
            known.calibration.lightDistance == calibration.lightDistance &&
            known.calibration.responseGamma == calibration.responseGamma &&
            known.harmonics == harmonics && known.lambda == lambda && known.folds == folds_) {
            return known.rms;
        }
    }
    const double rms = validator_.score(calibration, harmonics, lambda, folds_);
    result_.trials.push_back({calibration, harmonics, lambda, folds_, rms});
    if (result_.trials.size() == 1 || rms < result_.rms) {
        result_.calibration = calibration;
        result_.harmonics = harmonics;
        result_.lambda = lambda;
        result_.rms = rms;
    }
    return rms;
}

// From here on scored over `next`: the choice so far, scored so, is the one to beat.
void HeldOutSearch::judgeBy(HeldOutFolds next) {
    if (next == folds_) {
        return;
    }
    folds_ = next;
    result_.rms = validator_.score(result_.calibration, result_.harmonics, result_.lambda, folds_);
    result_.trials.push_back(
        {result_.calibration, result_.harmonics, result_.lambda, folds_, result_.rms});
}

// Coordinate descent on the field of view (degrees) and the light distance (image
// half-widths, 0 = far) from the choice so far, the steps shrinking each round.
void HeldOutSearch::refineGeometry(int rounds) {
    double fovStep = 5.0;
    double distanceFactor = 1.25;
    for (int round = 0; round < rounds; ++round) {
        bool improved = true;
        while (improved) {
            const HeldOutSearchResult before = result_;
            for (double delta : {-fovStep, fovStep}) {
                const double fov = before.calibration.fieldOfViewDegrees + delta;
                if (fov >= 0 && fov <= 90) {
                    score({fov,
                           before.calibration.lightDistance,
                           before.calibration.responseGamma,
                           {}},
                          before.harmonics, before.lambda);
                }
            }
            if (before.calibration.lightDistance > 0) {
                for (double factor : {1.0 / distanceFactor, distanceFactor}) {
                    const double distance = before.calibration.lightDistance * factor;
                    if (distance >= 1.5 && distance <= 100) {
                        score({before.calibration.fieldOfViewDegrees,
                               distance,
                               before.calibration.responseGamma,
                               {}},
                              before.harmonics, before.lambda);
                    }
                }
            }
            improved = result_.rms < before.rms;
        }
        fovStep /= 2;
        distanceFactor = std::sqrt(distanceFactor);
    }
}

// The lights a held-out fit trains on: all but one in holdOutEvery.
int HeldOutSearch::trainingLights() const {
    return static_cast<int>(capture_.images.size()) -
           static_cast<int>(capture_.images.size()) / options_.holdOutEvery;
}

// The camera response first: the shape of shading over the lights depends on it more
// than on anything else (realrti-dev: sRGB decoding of nearly linear JPEGs made a canvas
// fall off as cos^2.3 and lose 9 dB on lower lights), and the geometry search below
// works under it.
// Each response is judged by its best of a few regularizations: at one fixed M and λ the
// choice leans towards whichever curve suits that smoothness (realrti-dev item3: γ 1.7 at
// M = 10, λ = 3.14, γ 1.0 once λ may be small; 1.0 predicted its held-out lights 1.7 dB
// better).
void HeldOutSearch::searchResponse() {
    for (double gamma : {0.0, 1.0, 1.2, 1.4, 1.7, 2.0, 2.4}) {
        for (int harmonics : {6, 10}) {
            if (proto::coefficientCount(harmonics) > trainingLights()) {
                continue;
            }
            for (double lambda : {0.03, 0.3, 3.14}) {
                score({0.0, 0.0, gamma, {}}, harmonics, lambda);
            }
        }
    }
}

// Geometry: a coarse grid of field of view and light distance under the response chosen,
// then coordinate descent with shrinking steps.
void HeldOutSearch::searchGeometry() {
    const double gamma = result_.calibration.responseGamma;
    for (double fov : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0}) {
        for (double distance : {0.0, 32.0, 16.0, 8.0, 6.0, 4.0, 3.0}) {
            score({fov, distance, gamma, {}}, options_.harmonics, options_.lambda);
        }
    }
    refineGeometry(3);
}

// Regularization under the chosen geometry; the paper's M = 10, λ = 3.14 is one of the
// candidates, so selection can only keep or improve the held-out error.
void HeldOutSearch::searchRegularization() {
    judgeBy(HeldOutFolds::kOne);
    const capture::GeometryCalibration geometry = result_.calibration;
    for (int harmonics : {6, 10, 15}) {
        if (proto::coefficientCount(harmonics) > trainingLights()) {
            continue;  // the held-out fit could not determine the coefficients
        }
        for (double lambda : {0.03, 0.1, 0.3, 1.0, 3.14, 10.0}) {
            score(geometry, harmonics, lambda);
        }
    }
    if (options_.calibrateGeometry) {
        judgeBy(HeldOutFolds::kEvery);
        refineGeometry(1);  // the geometry may shift a little with a sharper BRDF
    }
}

// The stated geometry at the given M and λ, scored as the choice was.
void HeldOutSearch::scoreStatedGeometry() {
    const auto stated =
        std::find_if(result_.trials.begin(), result_.trials.end(), [&](const HeldOutTrial& trial) {
            return trial.calibration.fieldOfViewDegrees == 0 &&
                   trial.calibration.lightDistance == 0 && trial.calibration.responseGamma == 0 &&
                   trial.harmonics == options_.harmonics && trial.lambda == options_.lambda &&
                   trial.folds == folds_;
        });
    result_.baselineRms = stated != result_.trials.end()
                              ? stated->rms
                              : validator_.score(capture::GeometryCalibration{}, options_.harmonics,
                                                 options_.lambda, folds_);
}

// The extended fit under everything chosen so far (T's ridge left at its default).
fit::ExtendedFitSettings HeldOutSearch::extendedSettings() const {
    fit::ExtendedFitSettings settings;
    settings.harmonics = result_.harmonics;
    settings.lambda = result_.lambda;
    settings.normalSearchDegrees = options_.normalSearchDegrees;
    return settings;
}

// T's ridge, by the extended fit under everything chosen above. A weak pull lets T draw
// the sharper shadows of raking lights (realrti-dev item7, lights 1–6° above the horizon);
// a strong one keeps T from explaining noise where there are few lights.
void HeldOutSearch::searchTransportRidge() {
    fit::ExtendedFitSettings settings = extendedSettings();
    for (double ridge : {1.0, 0.3, 0.1, 0.03, 0.01}) {
        settings.transportRidge = ridge;
        const double rms = validator_.scoreWithTransport(result_.calibration, settings).pooled;
        result_.transportTrials.push_back({ridge, rms});
        if (result_.transportTrials.size() == 1 || rms < result_.transportRms) {
            result_.transportRidge = ridge;
            result_.transportRms = rms;
        }
    }
}

// The blocked lights, under T's ridge: on every fold a table calibrated on the other three
// quarters of the lights predicts that fold, and the tables are kept, calibrated again on
// every light, when they predict the folds better than the lights as stated. Judged on one
// fold, the choice followed the draw: realrti-dev item7 (rotation r2 of the protocol) kept
// no table, its fold's per-image RMS 9.3 against 4.9 as stated, where the table gained
// 2.5 dB on the capture's test lights; a held-out light beside the blocked ones takes their
// intensity in part (lightIntensityAt), and one fold holds few such lights.
void HeldOutSearch::searchLightIntensities() {
    fit::ExtendedFitSettings settings = extendedSettings();
    settings.transportRidge = result_.transportRidge;
    auto anyBlocked = [](const std::vector<capture::LightIntensity>& table) {
        return std::any_of(table.begin(), table.end(), [](const capture::LightIntensity& entry) {
            return entry.intensity < 1;
        });
    };
    // Judged by the images' mean PSNR, as vpe eval reports it: the lights this
    // calibrates are the dark ones, which pooling over all samples barely counts.
    const HeldOutScore stated =
        validator_.scoreWithTransport(result_.calibration, settings, HeldOutFolds::kEvery);
    result_.lightIntensityStatedRms = stated.imageMean;
    result_.lightIntensityRms = stated.imageMean;
    everyFold_ = stated;
    // The table of every light first: when it blocks none, there is nothing to judge.
    std::vector<capture::LightIntensity> table =
        calibrateLightIntensities(validator_, capture_, result_.calibration, settings,
                                  options_.holdOutEvery, -1)
            .lightIntensities;
    if (!anyBlocked(table)) {
        return;  // the lights as stated, as the model file says
    }
    std::vector<capture::GeometryCalibration> byFold;
    for (int fold = 0; fold < options_.holdOutEvery; ++fold) {
        byFold.push_back(calibrateLightIntensities(validator_, capture_, result_.calibration,
                                                   settings, options_.holdOutEvery, fold));
    }
    const HeldOutScore withTables = validator_.scoreWithTransportByFold(byFold, settings);
    result_.lightIntensityRms = withTables.imageMean;
    // A table is a free intensity per blocked light: kept when it gains at least 0.1 dB on
    // the folds. On realrti-dev item3 the folds kept three lights at 0.81–0.9 of the median
    // for 0.04 dB (7.845 against 7.883 levels) and its test lights lost 0.23 dB; item7 gains
    // 0.18 dB (r0) to 1.8 dB (r2).
    constexpr double kLeastGainDb = 0.1;
    if (20 * std::log10(stated.imageMean / withTables.imageMean) >= kLeastGainDb) {
        result_.calibration.lightIntensities = std::move(table);
        // Each fold's lights judged under a table that did not see them: the table of every
        // light knows the held-out lights' own intensities.
        everyFold_ = withTables;
    }
}

// The extended model as chosen and the classic bases on every fold: a criterion that does not
// depend on which quarter of the lights happens to be held out (one fold moved realrti-dev
// item7's comparison with HSH-16 by ±0.5 dB from one draw to the next).
void HeldOutSearch::compareClassicBases() {
    fit::ExtendedFitSettings settings = extendedSettings();
    settings.transportRidge = result_.transportRidge;
    // Scored already by the blocked-light stage.
    result_.extendedEveryFold =
        everyFold_
            ? *everyFold_
            : validator_.scoreWithTransport(result_.calibration, settings, HeldOutFolds::kEvery);
    for (const char* name : {"ptm6", "hsh9", "hsh16"}) {
        const model::RtiBasis basis = *model::RtiBasis::parse(name);
        if (basis.terms <= trainingLights() - trainingLights() / options_.holdOutEvery) {
            result_.classicBases.push_back(
                {name, validator_.scoreRtiBasis(basis, HeldOutFolds::kEvery)});
        }
    }
}

}  // namespace

std::vector<std::uint8_t> heldOutGridPixels(const normals::NormalMap& normals, int samplePixels) {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(normals.width) * normals.height, 0);
    forEachGridPixel(normals, samplePixels, [&](int x, int y) {
        pixels[static_cast<std::size_t>(y) * normals.width + x] = 1;
    });
    return pixels;
}

std::vector<std::uint8_t> heldOutGridPixels(const std::vector<std::uint8_t>& candidates, int width,
                                            int height, double validShare, int samplePixels) {
    const auto count = static_cast<double>(
        std::count_if(candidates.begin(), candidates.end(), [](std::uint8_t c) { return c != 0; }));
    std::vector<std::uint8_t> pixels(candidates.size(), 0);
    forEachGridPixel(
        width, height, count * validShare, samplePixels,
        [&](int x, int y) { return candidates[static_cast<std::size_t>(y) * width + x] != 0; },
        [&](int x, int y) { pixels[static_cast<std::size_t>(y) * width + x] = 1; });
    return pixels;
}

// Photometric stereo on the held-out search's grid alone (each pixel's estimate is its own,
// so these are the whole map's normals there). The grid's lattice follows the share of pixels
// that get a normal: every candidate at first (on realrti-dev every pixel gets one, and the
// grid is the whole map's); where some do not, the lattice is laid again for the share that
// did.
normals::NormalMap heldOutGridNormals(const capture::Capture& capture,
                                      const std::vector<std::uint8_t>& mask, int width, int height,
                                      int samplePixels, unsigned threads) {
    const std::vector<std::uint8_t> candidates =
        mask.empty() ? std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height, 1)
                     : mask;
    normals::PhotometricStereoOptions stereo;
    stereo.threads = threads;
    std::vector<std::uint8_t> grid =
        heldOutGridPixels(candidates, width, height, 1.0, samplePixels);
    stereo.pixels = &grid;
    normals::NormalMap estimated = normals::estimateNormals(capture, stereo);
    const auto tried = static_cast<double>(std::count(grid.begin(), grid.end(), 1));
    const auto found =
        static_cast<double>(std::count(estimated.valid.begin(), estimated.valid.end(), 1));
    if (found < tried) {
        std::vector<std::uint8_t> again =
            heldOutGridPixels(candidates, width, height, found / tried, samplePixels);
        if (again != grid) {
            grid = std::move(again);
            estimated = normals::estimateNormals(capture, stereo);
        }
    }
    return estimated;
}

HeldOutSearchResult searchHeldOut(const capture::Capture& capture,
                                  const normals::NormalMap& normals,
                                  const HeldOutSearchOptions& options) {
    return HeldOutSearch(capture, normals, options).run();
}

}  // namespace vpe::fit
