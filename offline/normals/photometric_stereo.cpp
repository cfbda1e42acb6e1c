// SPDX-License-Identifier: MIT
// Robust photometric stereo: rank trimming, then Tukey IRLS, per pixel.
#include "vpe/normals/photometric_stereo.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Dense>

#include "vpe/capture/image_band_reader.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/luminance.h"

namespace vpe::normals {

namespace {

struct Sample {
    Eigen::Vector3d light;  // unit direction towards the light
    double luminance;       // normalized to unit irradiance
};

// Weighted least squares for the scaled normal g in y ≈ l·g.
bool solveScaledNormal(const std::vector<Sample>& samples, const std::vector<double>& weights,
                       Eigen::Vector3d& g) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int used = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (weights[i] <= 0) {
            continue;
        }
        a.noalias() += weights[i] * samples[i].light * samples[i].light.transpose();
        b.noalias() += weights[i] * samples[i].luminance * samples[i].light;
        ++used;
    }
    if (used < 3) {
        return false;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(a);
    // Lights nearly in one plane leave the normal undetermined.
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-6 * a.trace())) {
        return false;
    }
    g = ldlt.solve(b);
    return g.allFinite() && g.norm() > 1e-12;
}

bool estimatePixelNormal(std::vector<Sample>& samples, const PhotometricStereoOptions& options,
                         Eigen::Vector3d& normal) {
    const std::size_t n = samples.size();
    if (n < 3) {
        return false;
    }
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return samples[a].luminance < samples[b].luminance;
    });
    const auto dark = static_cast<std::size_t>(options.darkFraction * static_cast<double>(n));
    const auto bright = static_cast<std::size_t>(options.brightFraction * static_cast<double>(n));
    std::vector<double> weights(n, 0.0);
    for (std::size_t r = dark; r + bright < n; ++r) {
        weights[order[r]] = 1.0;
    }
    Eigen::Vector3d g;
    if (!solveScaledNormal(samples, weights, g)) {
        std::fill(weights.begin(), weights.end(), 1.0);
        if (!solveScaledNormal(samples, weights, g)) {
            return false;
        }
    }
    std::vector<double> residuals(n);
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
        std::vector<double> magnitudes;
        for (std::size_t i = 0; i < n; ++i) {
            residuals[i] = samples[i].luminance - samples[i].light.dot(g);
            // A light below the surface's horizon says nothing about a Lambertian normal.
            if (samples[i].light.dot(g) > 0) {
                magnitudes.push_back(std::fabs(residuals[i]));
            }
        }
        if (magnitudes.size() < 3) {
            break;
        }
        std::nth_element(magnitudes.begin(),
                         magnitudes.begin() + static_cast<long>(magnitudes.size() / 2),
                         magnitudes.end());
        const double scale = std::max(1.4826 * magnitudes[magnitudes.size() / 2], 1e-6 * g.norm());
        const double cutoff = 4.685 * scale;
        for (std::size_t i = 0; i < n; ++i) {
            const double u = residuals[i] / cutoff;
            weights[i] =
                (samples[i].light.dot(g) > 0 && std::fabs(u) < 1) ? (1 - u * u) * (1 - u * u) : 0.0;
        }
        Eigen::Vector3d next;
        if (!solveScaledNormal(samples, weights, next)) {
            break;
        }
        g = next;
    }
    normal = g.normalized();
    return true;
}

}  // namespace

NormalMap estimateNormals(const capture::Capture& capture,
                          const PhotometricStereoOptions& options) {
    capture::ImageBandReader reader(capture, options.threads);
    const int width = reader.width();
    const int height = reader.height();
    std::vector<std::uint8_t> mask;
    if (capture.mask) {
        const image::FloatImage image = image::readImage(*capture.mask);
        mask.resize(static_cast<std::size_t>(width) * height);
        for (std::size_t i = 0; i < mask.size(); ++i) {
            mask[i] = image.pixels[i * static_cast<std::size_t>(image.channels)] > 0 ? 1 : 0;
        }
    }
    const capture::SurfaceGeometry geometry(capture, width, height);

    NormalMap normals;
    normals.resize(width, height);
    const int bandRows = reader.rowsForBudget(std::size_t{128} << 20);
    capture::SampleBand band;
    common::ProgressBar progress("normals", static_cast<std::size_t>(height));
    for (int rowBegin = 0; rowBegin < height; rowBegin += bandRows) {
        const int rows = std::min(bandRows, height - rowBegin);
        reader.readBand(rowBegin, rows, mask.empty() ? nullptr : mask.data(), band);
        common::parallelFor(
            static_cast<std::size_t>(rows) * width, 64, options.threads,
            [&](std::size_t begin, std::size_t end) {
                std::vector<Sample> samples;
                for (std::size_t p = begin; p < end; ++p) {
                    const int r = static_cast<int>(p / static_cast<std::size_t>(width));
                    const int x = static_cast<int>(p % static_cast<std::size_t>(width));
                    const int y = rowBegin + r;
                    if (options.pixels != nullptr &&
                        (*options.pixels)[static_cast<std::size_t>(y) * width + x] == 0) {
                        continue;
                    }
                    samples.clear();
                    const proto::Vec3d position = geometry.position(x, y);
                    for (int s = 0; s < band.images; ++s) {
                        if (band.weight(s, r, x) <= 0 || band.isSaturated(s, r, x)) {
                            continue;
                        }
                        const capture::IncidentLight light = capture::incidentLight(
                            capture, capture.images[static_cast<std::size_t>(s)], position);
                        const double luminance = proto::luminance709(
                            band.value(s, 0, r, x), band.value(s, 1, r, x), band.value(s, 2, r, x));
                        samples.push_back({Eigen::Vector3d(light.direction.x, light.direction.y,
                                                           light.direction.z),
                                           luminance / light.irradiance});
                    }
                    Eigen::Vector3d n;
                    if (estimatePixelNormal(samples, options, n)) {
                        const std::size_t i = normals.index(x, y);
                        for (int c = 0; c < 3; ++c) {
                            normals.xyz[i * 3 + c] = static_cast<float>(n[c]);
                        }
                        normals.valid[i] = 1;
                    }
                }
            });
        progress.advance(static_cast<std::size_t>(rows));
    }
    progress.finish();
    return normals;
}

}  // namespace vpe::normals
