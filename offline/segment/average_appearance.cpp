// SPDX-License-Identifier: MIT
// Average appearance: the model rendered under a dome and averaged; clustering features.
#include "vpe/segment/average_appearance.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <Eigen/Dense>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/principal_axes.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::segment {

namespace {

constexpr int kAveragingLights = 40;
constexpr int kBandRows = 64;

double labCompand(double t) {
    // CIE 1976: cube root above (6/29)³, a line below it so the curve is continuous.
    constexpr double kEpsilon = 216.0 / 24389.0;
    constexpr double kKappa = 24389.0 / 27.0;
    return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0;
}

// Group variance (sum over its dimensions) over the valid pixels.
double groupVariance(const Appearance& a, int first, int count) {
    std::vector<double> mean(static_cast<std::size_t>(count), 0.0);
    for (std::size_t p = 0; p < a.valid.size(); ++p) {
        if (a.valid[p]) {
            for (int d = 0; d < count; ++d) {
                mean[static_cast<std::size_t>(d)] +=
                    static_cast<double>(a.features[p * static_cast<std::size_t>(a.featureCount) +
                                                   static_cast<std::size_t>(first + d)]);
            }
        }
    }
    for (double& m : mean) {
        m /= static_cast<double>(std::max<std::size_t>(a.validPixels, 1));
    }
    double variance = 0;
    for (std::size_t p = 0; p < a.valid.size(); ++p) {
        if (a.valid[p]) {
            for (int d = 0; d < count; ++d) {
                const double v =
                    static_cast<double>(a.features[p * static_cast<std::size_t>(a.featureCount) +
                                                   static_cast<std::size_t>(first + d)]) -
                    mean[static_cast<std::size_t>(d)];
                variance += v * v;
            }
        }
    }
    return variance / static_cast<double>(std::max<std::size_t>(a.validPixels, 1));
}

void scaleGroup(Appearance& a, int first, int count) {
    const double variance = groupVariance(a, first, count);
    // A uniform group (one material) has nothing to scale; leave it at zero spread.
    if (!(variance > 1e-20)) {
        return;
    }
    const float scale = static_cast<float>(1.0 / std::sqrt(variance));
    for (std::size_t p = 0; p < a.valid.size(); ++p) {
        for (int d = 0; d < count; ++d) {
            a.features[p * static_cast<std::size_t>(a.featureCount) +
                       static_cast<std::size_t>(first + d)] *= scale;
        }
    }
}

// The model a band of kBandRows rows at a time, so that a large model's coefficients need not
// fit in memory at once: `rowsWork(rowBegin, begin, end)` on the band's rows [begin, end) on the
// worker threads, then `bandDone(rowBegin, count)` on this one, before the next band replaces
// `rows`.
template <typename RowsWork, typename BandDone>
void forEachBand(model::ModelReader& reader, int height, int threads, model::ModelRows& rows,
                 RowsWork rowsWork, BandDone bandDone) {
    for (int rowBegin = 0; rowBegin < height; rowBegin += kBandRows) {
        const int count = std::min(kBandRows, height - rowBegin);
        reader.readRows(rowBegin, count, rows);
        common::parallelFor(
            static_cast<std::size_t>(count), 1, threads,
            [&](std::size_t begin, std::size_t end) { rowsWork(rowBegin, begin, end); });
        bandDone(rowBegin, count);
    }
}

}  // namespace

const std::vector<proto::Vec3d>& averagingLights() {
    // A Fibonacci lattice on the hemisphere: z uniform in (0, 1) is uniform in solid angle,
    // and the golden-angle azimuths spread the rings without gaps or clusters.
    static const std::vector<proto::Vec3d> kLights = [] {
        std::vector<proto::Vec3d> lights;
        const double goldenAngle = M_PI * (3.0 - std::sqrt(5.0));
        for (int i = 0; i < kAveragingLights; ++i) {
            const double z = 1.0 - (i + 0.5) / kAveragingLights;
            const double r = std::sqrt(1.0 - z * z);
            lights.push_back({r * std::cos(i * goldenAngle), r * std::sin(i * goldenAngle), z});
        }
        return lights;
    }();
    return kLights;
}

void linearRgbToLab(const float* rgb, float* lab) {
    const double r = static_cast<double>(rgb[0]);
    const double g = static_cast<double>(rgb[1]);
    const double b = static_cast<double>(rgb[2]);
    // sRGB primaries to XYZ, normalized by the D65 white's X and Z. Y is the matrix's middle
    // row at the matrix's precision, not proto::luminance709's rounded Rec. 709 weights: the
    // three rows belong together, and the labels stay those segment has always given.
    const double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
    const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
    const double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
    const double fx = labCompand(x), fy = labCompand(y), fz = labCompand(z);
    lab[0] = static_cast<float>(116.0 * fy - 16.0);
    lab[1] = static_cast<float>(500.0 * (fx - fy));
    lab[2] = static_cast<float>(200.0 * (fy - fz));
}

Appearance computeAppearance(const std::filesystem::path& modelPath,
                             const AppearanceOptions& options) {
    model::ModelReader reader(modelPath);
    const model::ModelInfo& info = reader.info();
    const int k = proto::coefficientCount(info.harmonics);
    const int dims = 3 * k;
    const int components = std::clamp(options.components, 1, dims);
    Appearance a;
    a.width = info.width;
    a.height = info.height;
    const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
    a.valid.assign(pixels, 0);
    a.average.assign(pixels * 3, 0.0f);
    a.lab.assign(pixels * 3, 0.0f);
    a.featureCount = 3 + components;
    a.features.assign(pixels * static_cast<std::size_t>(a.featureCount), 0.0f);

    // Pass 1: the average under the dome, and the coefficients of evenly spread samples.
    const std::size_t stride =
        std::max<std::size_t>(1, (pixels + options.pcaSamples - 1) / options.pcaSamples);
    std::vector<float> samples;
    model::ModelRows rows;
    const proto::Vec3d view{0, 0, 1};
    const std::vector<proto::Vec3d>& lights = averagingLights();
    forEachBand(
        reader, a.height, options.threads, rows,
        [&](int rowBegin, std::size_t begin, std::size_t end) {
            for (std::size_t r = begin; r < end; ++r) {
                const int row = static_cast<int>(r);
                for (int x = 0; x < a.width; ++x) {
                    const std::size_t local = rows.pixel(row, x);
                    if (!rows.valid[local]) {
                        continue;
                    }
                    const std::size_t p = a.pixel(x, rowBegin + row);
                    a.valid[p] = 1;
                    const float* n = &rows.normal[local * 3];
                    const proto::Vec3d normal{static_cast<double>(n[0]), static_cast<double>(n[1]),
                                              static_cast<double>(n[2])};
                    double sum[3] = {0, 0, 0};
                    for (const proto::Vec3d& light : lights) {
                        const auto angles = proto::reflectionAngles(normal, light, view);
                        // A light below the surface's horizon does not reach it,
                        // whatever the series extrapolates to there.
                        if (angles.cosThetaD <= 0) {
                            continue;
                        }
                        for (int c = 0; c < 3; ++c) {
                            sum[c] +=
                                std::max(0.0, proto::evaluateFourierBrdf(
                                                  rows.coefficientsAt(row, x, c), info.harmonics,
                                                  angles.cosThetaD, angles.cosThetaS));
                        }
                    }
                    for (int c = 0; c < 3; ++c) {
                        a.average[p * 3 + static_cast<std::size_t>(c)] =
                            static_cast<float>(sum[c] / static_cast<double>(lights.size()));
                    }
                    linearRgbToLab(&a.average[p * 3], &a.lab[p * 3]);
                }
            }
        },
        [&](int rowBegin, int count) {
            for (int row = 0; row < count; ++row) {
                for (int x = 0; x < a.width; ++x) {
                    const std::size_t p = a.pixel(x, rowBegin + row);
                    if (a.valid[p] && p % stride == 0) {
                        const float* c = rows.coefficientsAt(row, x, 0);
                        samples.insert(samples.end(), c, c + dims);
                    }
                }
            }
        });
    for (std::uint8_t v : a.valid) {
        a.validPixels += v;
    }
    if (a.validPixels == 0) {
        throw common::InputError(modelPath, "no valid pixels");
    }

    // Principal axes of the coefficients: the 3(2M + 2) values are strongly correlated (the
    // three channels, the harmonics of one lobe), so a few axes hold most of the variation
    // between materials, and the noisy rest stays out of the distances.
    const common::PrincipalAxes pca = common::principalAxes(
        samples.size() / static_cast<std::size_t>(dims), dims,
        [&](std::size_t i) { return &samples[i * static_cast<std::size_t>(dims)]; },
        common::AxisSelection{.maxAxes = components});
    const Eigen::MatrixXd& axes = pca.axes;
    const Eigen::RowVectorXd mean = pca.mean.transpose();
    a.explainedVariance = pca.explained();

    // Pass 2: the features.
    forEachBand(
        reader, a.height, options.threads, rows,
        [&](int rowBegin, std::size_t begin, std::size_t end) {
            Eigen::VectorXd c(dims);
            for (std::size_t r = begin; r < end; ++r) {
                const int row = static_cast<int>(r);
                for (int x = 0; x < a.width; ++x) {
                    const std::size_t p = a.pixel(x, rowBegin + row);
                    if (!a.valid[p]) {
                        continue;
                    }
                    const float* values = rows.coefficientsAt(row, x, 0);
                    for (int d = 0; d < dims; ++d) {
                        c(d) = static_cast<double>(values[d]) - mean(d);
                    }
                    float* f = &a.features[p * static_cast<std::size_t>(a.featureCount)];
                    for (int d = 0; d < 3; ++d) {
                        f[d] = a.lab[p * 3 + static_cast<std::size_t>(d)];
                    }
                    const Eigen::VectorXd projected = axes.transpose() * c;
                    for (int i = 0; i < components; ++i) {
                        f[3 + i] = static_cast<float>(projected(i));
                    }
                }
            }
        },
        [](int, int) {});
    // Each group to unit total variance, so colour and reflectance weigh alike whatever their
    // units. Within a group the space's own metric is kept: CIELAB is perceptually even, and
    // whitening each component would blow the noisiest up to the weight of the main one.
    scaleGroup(a, 0, 3);
    scaleGroup(a, 3, components);
    return a;
}

}  // namespace vpe::segment
