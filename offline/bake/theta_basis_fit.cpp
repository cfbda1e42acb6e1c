// SPDX-License-Identifier: MIT
// The θs basis by eigen-decompositions of two (2M + 1)-square matrices: the Gram matrix, to
// change to coordinates in which ∫₀^π is the plain dot product, and the second moment there.
#include "vpe/bake/theta_basis_fit.h"

#include <algorithm>
#include <string>

#include <Eigen/Eigenvalues>

#include "vpe/common/input_error.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/theta_basis.h"

namespace vpe::bake {

namespace {

// Below this share of the largest eigenvalue, a direction of the Gram matrix is a function
// that vanishes on [0, π] to rounding: normalizing it would need coefficients of 1e5 and more,
// which floats cannot hold orthonormal.
constexpr double kGramCutoff = 1e-10;

// Samples gathered before one rank update of S: large enough for Eigen's blocked product.
constexpr Eigen::Index kChunkSamples = 3 * 1024;

Eigen::MatrixXd thetaGramMatrix(int n) {
    Eigen::MatrixXd gram(n, n);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            gram(i, j) = proto::thetaGram(i, j);
        }
    }
    return gram;
}

// The Gram matrix's kept eigenvectors (columns) and the square roots of their eigenvalues.
struct GramRoot {
    Eigen::MatrixXd vectors;
    Eigen::VectorXd roots;
};

GramRoot gramRoot(int harmonics) {
    const int n = proto::thetaFunctionCount(harmonics);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(thetaGramMatrix(n));
    // Eigenvalues come in increasing order: the kept ones are the last columns.
    const Eigen::VectorXd& values = solver.eigenvalues();
    const double cutoff = kGramCutoff * values[n - 1];
    Eigen::Index first = 0;
    while (first < n && !(values[first] > cutoff)) {
        ++first;
    }
    GramRoot root;
    root.vectors = solver.eigenvectors().rightCols(n - first);
    root.roots = values.tail(n - first).cwiseSqrt();
    return root;
}

}  // namespace

ThetaMoment::ThetaMoment(int harmonics)
    : harmonics_(harmonics),
      moment_(static_cast<std::size_t>(proto::thetaFunctionCount(harmonics)) *
                  static_cast<std::size_t>(proto::thetaFunctionCount(harmonics)),
              0.0) {}

void ThetaMoment::add(std::span<const float> coefficients, std::span<const unsigned char> valid) {
    const int n = proto::thetaFunctionCount(harmonics_);
    const auto perTexel = static_cast<std::size_t>(3 * proto::coefficientCount(harmonics_));
    const std::size_t texels = coefficients.size() / perTexel;
    Eigen::Map<Eigen::MatrixXd> moment(moment_.data(), n, n);
    Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(n, n);
    Eigen::MatrixXd chunk(n, kChunkSamples);
    Eigen::Index filled = 0;
    const auto flush = [&] {
        lower.selfadjointView<Eigen::Lower>().rankUpdate(chunk.leftCols(filled));
        samples_ += static_cast<std::size_t>(filled);
        filled = 0;
    };
    for (std::size_t t = 0; t < texels; ++t) {
        if (!valid.empty() && valid[t] == 0) {
            continue;
        }
        const float* texel = coefficients.data() + t * perTexel;
        for (int c = 0; c < 3; ++c) {
            for (int i = 0; i < n; ++i) {
                // θ-function i is model coefficient i + 1 (kd first).
                chunk(i, filled) =
                    static_cast<double>(texel[proto::bundleCoefficientIndex(i + 1, c)]);
            }
            if (++filled == kChunkSamples) {
                flush();
            }
        }
    }
    flush();
    moment += Eigen::MatrixXd(lower.selfadjointView<Eigen::Lower>());
}

int independentThetaFunctions(int harmonics) {
    return static_cast<int>(gramRoot(harmonics).roots.size());
}

ThetaBasisFit fitThetaBasis(const ThetaMoment& moment, int size) {
    const int harmonics = moment.harmonics();
    const int n = proto::thetaFunctionCount(harmonics);
    const GramRoot root = gramRoot(harmonics);
    const auto independent = static_cast<int>(root.roots.size());
    if (size < 1 || size > independent) {
        throw common::InputError("θs basis: " + std::to_string(size) + " functions, outside 1.." +
                                 std::to_string(independent) + " (the θs functions of M = " +
                                 std::to_string(harmonics) + " independent over [0, π])");
    }
    const Eigen::Map<const Eigen::MatrixXd> s(moment.moment().data(), n, n);
    // In coordinates y = Λ^½ Vᵀ c (c a function's coefficients), ∫₀^π is the dot product: the
    // second moment there is Λ^½ Vᵀ S V Λ^½, whose eigenvectors are orthonormal functions.
    const Eigen::MatrixXd scaled = root.vectors * root.roots.asDiagonal();
    const Eigen::MatrixXd reduced = scaled.transpose() * s * scaled;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(reduced);
    const Eigen::MatrixXd back = root.vectors * root.roots.cwiseInverse().asDiagonal();

    ThetaBasisFit fit;
    fit.functions.resize(static_cast<std::size_t>(size) * static_cast<std::size_t>(n));
    double kept = 0;
    for (int j = 0; j < size; ++j) {
        const Eigen::Index column = independent - 1 - j;  // increasing order: largest last
        Eigen::VectorXd function = back * solver.eigenvectors().col(column);
        Eigen::Index largest = 0;
        function.cwiseAbs().maxCoeff(&largest);
        if (function[largest] < 0) {
            function = -function;
        }
        for (int i = 0; i < n; ++i) {
            fit.functions[static_cast<std::size_t>(j * n + i)] = static_cast<float>(function[i]);
        }
        kept += std::max(solver.eigenvalues()[column], 0.0);
    }
    // The device checks its basis as floats. The last of the independent directions are sums
    // of sines and cosines that nearly cancel on [0, π]: their coefficients reach 1e4, and
    // rounding them to floats can cost the orthonormality the device requires (1e-4). Only
    // a K close to independentThetaFunctions(M) on textures that use those directions does.
    if (const std::string problem = proto::checkThetaBasis(harmonics, fit.functions);
        !problem.empty()) {
        throw common::InputError(
            "the " + std::to_string(size) +
            " fitted θs functions do not stay orthonormal once rounded to floats (" + problem +
            "); fit fewer");
    }
    // Σ ∫ g² = trace(G S), over every direction (the dropped ones hold ~1e-10 of it).
    const double total = (thetaGramMatrix(n) * s).trace();
    fit.energyKept = total > 0 ? std::min(kept / total, 1.0) : 1.0;
    return fit;
}

}  // namespace vpe::bake
