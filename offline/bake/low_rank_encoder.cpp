// SPDX-License-Identifier: MIT
// Principal components by the eigen-decomposition of the sampled covariance (C × C is tiny),
// then every texel projected onto them.
#include "bake/low_rank_encoder.h"

#include <algorithm>
#include <string>

#include <Eigen/Eigenvalues>

#include "common/input_error.h"
#include "common/parallel_for.h"

namespace vpe::bake {

LowRankCode encodeLowRank(const std::vector<float>& coefficients, int channels,
                          const std::vector<unsigned char>& valid, const LowRankOptions& options) {
    if (channels <= 0 || coefficients.size() % static_cast<std::size_t>(channels) != 0) {
        throw InputError("low-rank code: " + std::to_string(coefficients.size()) +
                         " values are not a whole number of " + std::to_string(channels) +
                         "-value texels");
    }
    if (options.rank < 1 || options.rank > channels) {
        throw InputError("low-rank code: rank " + std::to_string(options.rank) + " is outside 1.." +
                         std::to_string(channels));
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

    Eigen::VectorXd mean = Eigen::VectorXd::Zero(channels);
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(channels, channels);
    std::size_t samples = 0;
    for (std::size_t i = 0; i < used.size(); i += stride) {
        mean +=
            Eigen::Map<const Eigen::VectorXf>(&coefficients[used[i] * c], channels).cast<double>();
        ++samples;
    }
    if (samples > 0) {
        mean /= static_cast<double>(samples);
        for (std::size_t i = 0; i < used.size(); i += stride) {
            const Eigen::VectorXd d =
                Eigen::Map<const Eigen::VectorXf>(&coefficients[used[i] * c], channels)
                    .cast<double>() -
                mean;
            covariance.selfadjointView<Eigen::Lower>().rankUpdate(d);
        }
        covariance = covariance.selfadjointView<Eigen::Lower>();
        covariance /= static_cast<double>(samples);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
    // Eigenvalues come in increasing order: the principal axes are the last columns.
    const double total = std::max(solver.eigenvalues().sum(), 1e-300);

    LowRankCode code;
    code.channels = channels;
    code.rank = options.rank;
    code.mean.resize(c);
    for (std::size_t k = 0; k < c; ++k) {
        code.mean[k] = static_cast<float>(mean[static_cast<Eigen::Index>(k)]);
    }
    Eigen::MatrixXf basis(options.rank, channels);
    for (int r = 0; r < options.rank; ++r) {
        const Eigen::Index column = channels - 1 - r;
        Eigen::VectorXd axis = solver.eigenvectors().col(column);
        // A fixed sign (largest entry positive), so the code does not flip between builds.
        Eigen::Index largest = 0;
        axis.cwiseAbs().maxCoeff(&largest);
        if (axis[largest] < 0) {
            axis = -axis;
        }
        basis.row(r) = axis.cast<float>().transpose();
        code.explained.push_back(std::max(0.0, solver.eigenvalues()[column]) / total);
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
    const Eigen::VectorXf meanF = mean.cast<float>();
    parallelFor(texels, 4096, options.threads, [&](std::size_t begin, std::size_t end) {
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
