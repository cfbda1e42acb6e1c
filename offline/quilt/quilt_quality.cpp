// SPDX-License-Identifier: MIT
// Quilting quality of one region: reading the maps, gathering the samples, and the metrics
// (sliced Wasserstein, spectra, seams, verbatim copies; each in its own unit, quality_metrics.h).
#include "vpe/quilt/quilt_quality.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"

#include "quality_metrics.h"

namespace vpe::quilt {

namespace metrics {

// Indices 0..count-1, or `limit` of them evenly spread when there are more.
std::vector<std::size_t> evenSubset(std::size_t count, std::size_t limit) {
    std::vector<std::size_t> indices;
    const std::size_t n = std::min(count, limit);
    indices.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        indices.push_back(count <= limit ? i : i * count / limit);
    }
    return indices;
}

}  // namespace metrics

namespace {

using metrics::evenSubset;
using metrics::kNaN;

// The vectors of the given pixels, gathered contiguously.
std::vector<float> gather(const model::CoefficientImage& image,
                          const std::vector<std::size_t>& pixels) {
    std::vector<float> out(pixels.size() * static_cast<std::size_t>(image.dims));
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::copy_n(image.at(pixels[i]), image.dims, out.data() + i * image.dims);
    }
    return out;
}

std::vector<std::size_t> subsetOf(const std::vector<std::size_t>& pixels, std::size_t limit) {
    std::vector<std::size_t> out;
    for (std::size_t i : evenSubset(pixels.size(), limit)) {
        out.push_back(pixels[i]);
    }
    return out;
}

}  // namespace

RegionQuality measureRegionQuality(const model::CoefficientImage& source,
                                   const std::vector<std::uint8_t>& labels, int region,
                                   const model::CoefficientImage& output,
                                   const PositionMap& positions, const QualityOptions& options) {
    if (output.dims != source.dims) {
        throw common::InputError("region " + std::to_string(region) + ": the output has " +
                                 std::to_string(output.harmonics) + " harmonics, the source " +
                                 std::to_string(source.harmonics));
    }
    if (labels.size() != static_cast<std::size_t>(source.width) * source.height ||
        positions.width != output.width || positions.height != output.height) {
        throw common::InputError("region " + std::to_string(region) +
                                 ": labels or positions do not match the model sizes");
    }
    RegionQuality quality;
    quality.region = region;
    quality.outputPixels = static_cast<std::size_t>(output.width) * output.height;

    // The source region: labelled pixels with a valid fit (invalid ones hold zeros).
    std::vector<std::uint8_t> mask(labels.size());
    std::vector<std::size_t> sourcePixels;
    for (std::size_t p = 0; p < labels.size(); ++p) {
        mask[p] = labels[p] == region && source.valid[p] ? 1 : 0;
        if (mask[p]) {
            sourcePixels.push_back(p);
        }
    }
    quality.sourcePixels = sourcePixels.size();

    // Correctness and copy consistency.
    double maxDifference = 0;
    for (std::size_t p = 0; p < quality.outputPixels; ++p) {
        if (!positions.known(p)) {
            continue;
        }
        ++quality.positionedPixels;
        const std::size_t s =
            static_cast<std::size_t>(positions.sourceY[p]) * source.width + positions.sourceX[p];
        if (labels[s] == region) {
            ++quality.correctPixels;
        }
        const float* o = output.at(p);
        const float* v = source.at(s);
        for (int d = 0; d < output.dims; ++d) {
            maxDifference = std::max(
                maxDifference, std::fabs(static_cast<double>(o[d]) - static_cast<double>(v[d])));
        }
    }
    quality.correctness = quality.positionedPixels > 0
                              ? static_cast<double>(quality.correctPixels) /
                                    static_cast<double>(quality.positionedPixels)
                              : kNaN;
    quality.copyMaxDifference = quality.positionedPixels > 0 ? maxDifference : kNaN;

    // Distribution match.
    std::vector<std::size_t> outputPixels;
    for (std::size_t p = 0; p < quality.outputPixels; ++p) {
        if (output.valid[p]) {
            outputPixels.push_back(p);
        }
    }
    const std::size_t limit = options.wasserstein.maxSamples;
    const std::vector<float> outputSamples = gather(output, subsetOf(outputPixels, limit));
    const std::vector<float> sourceSamples = gather(source, subsetOf(sourcePixels, limit));
    const std::size_t half = sourcePixels.size() / 2;
    const std::vector<std::size_t> topHalf(
        sourcePixels.begin(), sourcePixels.begin() + static_cast<std::ptrdiff_t>(half));
    const std::vector<std::size_t> bottomHalf(
        sourcePixels.begin() + static_cast<std::ptrdiff_t>(half), sourcePixels.end());
    const std::vector<float> topSamples = gather(source, subsetOf(topHalf, limit));
    const std::vector<float> bottomSamples = gather(source, subsetOf(bottomHalf, limit));
    SlicedWassersteinOptions wasserstein = options.wasserstein;
    wasserstein.threads = options.threads;
    const auto dims = static_cast<std::size_t>(source.dims);
    quality.wasserstein =
        slicedWasserstein(outputSamples.data(), outputSamples.size() / dims, sourceSamples.data(),
                          sourceSamples.size() / dims, source.dims, wasserstein);
    quality.wassersteinSelf =
        slicedWasserstein(topSamples.data(), topSamples.size() / dims, bottomSamples.data(),
                          bottomSamples.size() / dims, source.dims, wasserstein);
    quality.wassersteinRatio = quality.wasserstein / quality.wassersteinSelf;

    metrics::measureSpectrum(source, mask, sourceSamples, output, options, quality);
    metrics::measureSeams(source, mask, output, positions, quality);
    metrics::measureLargestCopy(positions, quality);
    return quality;
}

}  // namespace vpe::quilt
