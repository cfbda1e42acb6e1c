// SPDX-License-Identifier: MIT
// Two passes over the samples (mean, then the centred scatter), then the eigen-decomposition
// of the dims × dims covariance: dims is small (at most the 3(2M + 2) coefficients of a texel).
#include "vpe/common/principal_axes.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace vpe::common {

double PrincipalAxes::explained() const {
    return std::min(1.0, variances.sum() / std::max(totalVariance, 1e-300));
}

PrincipalAxes principalAxes(std::size_t count, int dims, const SampleAt& sampleAt,
                            const AxisSelection& selection) {
    PrincipalAxes result;
    result.samples = count;
    result.mean = Eigen::VectorXd::Zero(dims);
    for (std::size_t i = 0; i < count; ++i) {
        result.mean += Eigen::Map<const Eigen::VectorXf>(sampleAt(i), dims).cast<double>();
    }
    if (count > 0) {
        result.mean /= static_cast<double>(count);
    }
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(dims, dims);
    for (std::size_t i = 0; i < count; ++i) {
        const Eigen::VectorXd d =
            Eigen::Map<const Eigen::VectorXf>(sampleAt(i), dims).cast<double>() - result.mean;
        covariance.selfadjointView<Eigen::Lower>().rankUpdate(d);
    }
    covariance = covariance.selfadjointView<Eigen::Lower>();
    if (count > 0) {
        covariance /= static_cast<double>(count);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
    // Eigen sorts eigenvalues ascending: the principal axes are the last columns.
    const Eigen::VectorXd values = solver.eigenvalues().reverse().cwiseMax(0.0);
    result.totalVariance = values.sum();
    const double total = std::max(result.totalVariance, 1e-300);
    int kept = 0;
    double sum = 0;
    const int most = std::min(selection.maxAxes, dims);
    while (kept < most && (kept == 0 || sum / total < selection.varianceToKeep)) {
        if (selection.dropBelow >= 0 &&
            !(values[kept] > selection.dropBelow * result.totalVariance &&
              result.totalVariance > 0)) {
            break;
        }
        sum += values[kept];
        ++kept;
    }
    result.axes.resize(dims, kept);
    result.variances = values.head(kept);
    for (int k = 0; k < kept; ++k) {
        Eigen::VectorXd axis = solver.eigenvectors().col(dims - 1 - k);
        Eigen::Index largest = 0;
        axis.cwiseAbs().maxCoeff(&largest);
        if (axis[largest] < 0) {
            axis = -axis;
        }
        result.axes.col(k) = axis;
    }
    return result;
}

}  // namespace vpe::common
