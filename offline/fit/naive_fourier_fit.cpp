// SPDX-License-Identifier: MIT
// The textbook per-pixel fit with Eigen.
#include "vpe/fit/naive_fourier_fit.h"

#include <Eigen/Cholesky>

#include "vpe/proto/fourier_brdf.h"

namespace vpe::fit {

NaiveFitResult fitPixelNaive(const std::vector<proto::ReflectionAngles<double>>& angles,
                             const Eigen::MatrixX3d& observations, const Eigen::VectorXd& weights,
                             int harmonics, double lambda) {
    const int k = proto::coefficientCount(harmonics);
    const auto n = static_cast<Eigen::Index>(angles.size());
    Eigen::MatrixXd design(n, k);
    std::vector<double> basis(static_cast<std::size_t>(k));
    for (Eigen::Index s = 0; s < n; ++s) {
        proto::fourierBasis(angles[s].cosThetaD, angles[s].cosThetaS, harmonics, basis.data());
        for (int j = 0; j < k; ++j) {
            design(s, j) = basis[static_cast<std::size_t>(j)];
        }
    }
    Eigen::MatrixXd normal = design.transpose() * weights.asDiagonal() * design;
    for (int j = 0; j < k; ++j) {
        normal(j, j) += lambda * proto::smoothnessWeight(j);
    }
    const Eigen::MatrixXd rhs = design.transpose() * weights.asDiagonal() * observations;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(normal);
    NaiveFitResult result;
    result.valid =
        ldlt.info() == Eigen::Success && (weights.array() > 0).count() >= k && ldlt.isPositive();
    result.coefficients =
        result.valid ? Eigen::MatrixX3d(ldlt.solve(rhs)) : Eigen::MatrixX3d::Zero(k, 3);
    return result;
}

}  // namespace vpe::fit
