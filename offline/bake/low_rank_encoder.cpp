// SPDX-License-Identifier: MIT
// Principal components of a sample of the texels (common/principal_axes.h), then every texel
// projected onto them.
#include "vpe/bake/low_rank_encoder.h"

#include <algorithm>
#include <string>

#include <Eigen/Core>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/principal_axes.h"

namespace vpe::bake {

LowRankCode encodeLowRank(const std::vector<float>& coefficients, int channels,
                          const std::vector<unsigned char>& valid, const LowRankOptions& options) {
    if (channels <= 0 || coefficients.size() % static_cast<std::size_t>(channels) != 0) {
        throw common::InputError("low-rank code: " + std::to_string(coefficients.size()) +
                                 " values are not a whole number of " + std::to_string(channels) +
                                 "-value texels");
    }
    if (options.rank < 1 || options.rank > channels) {
        throw common::InputError("low-rank code: rank " + std::to_string(options.rank) +
                                 " is outside 1.." + std::to_string(channels));
    }
    const std::size_t c = static_cast<std::size_t>(channels);
    const std::size_t texels = coefficients.size() / c;
    const auto isValid = [&](std::size_t t) { return valid.empty() || valid[t] != 0; };
    std::vector<std::size_t> used;
    for (std::size_t t = 0; t < texels; ++t) {
        if (isValid(t)) {
            used.push_back(t);
        }
    }
    const std::size_t stride =
        std::max<std::size_t>(1, used.size() / std::max<std::size_t>(1, options.maxSamples));

    const common::PrincipalAxes pca =
        common::principalAxes((used.size() + stride - 1) / stride, channels,
                              [&](std::size_t i) { return &coefficients[used[i * stride] * c]; },
                              common::AxisSelection{.maxAxes = options.rank});

    LowRankCode code;
    code.channels = channels;
    code.rank = options.rank;
    code.mean.resize(c);
    for (std::size_t k = 0; k < c; ++k) {
        code.mean[k] = static_cast<float>(pca.mean[static_cast<Eigen::Index>(k)]);
    }
    const Eigen::MatrixXf basis = pca.axes.transpose().cast<float>();
    for (int r = 0; r < options.rank; ++r) {
        code.explained.push_back(pca.variances[r] / std::max(pca.totalVariance, 1e-300));
    }
    code.basis.resize(static_cast<std::size_t>(options.rank) * c);
    for (int r = 0; r < options.rank; ++r) {
        for (std::size_t k = 0; k < c; ++k) {
            code.basis[static_cast<std::size_t>(r) * c + k] =
                basis(r, static_cast<Eigen::Index>(k));
        }
    }

    const std::size_t rank = static_cast<std::size_t>(options.rank);
    code.weights.assign(texels * rank, 0.0f);
    const Eigen::VectorXf meanF = pca.mean.cast<float>();
    common::parallelFor(texels, 4096, options.threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t) {
            if (!isValid(t)) {
                continue;  // μ: weights stay 0
            }
            const Eigen::VectorXf d =
                Eigen::Map<const Eigen::VectorXf>(&coefficients[t * c], channels) - meanF;
            Eigen::Map<Eigen::VectorXf>(&code.weights[t * rank], options.rank) = basis * d;
        }
    });
    return code;
}

std::vector<float> decodeLowRank(const LowRankCode& code) {
    const std::size_t c = static_cast<std::size_t>(code.channels);
    const std::size_t rank = static_cast<std::size_t>(code.rank);
    const std::size_t texels = rank ? code.weights.size() / rank : 0;
    std::vector<float> out(texels * c);
    for (std::size_t t = 0; t < texels; ++t) {
        for (std::size_t k = 0; k < c; ++k) {
            float value = code.mean[k];
            for (std::size_t r = 0; r < rank; ++r) {
                value += code.weights[t * rank + r] * code.basis[r * c + k];
            }
            out[t * c + k] = value;
        }
    }
    return out;
}

}  // namespace vpe::bake
