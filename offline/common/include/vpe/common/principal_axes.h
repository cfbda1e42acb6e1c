// SPDX-License-Identifier: MIT
// principalAxes: the principal axes of a set of vectors (PCA by the eigen-decomposition of
// their covariance, Eigen's SelfAdjointEigenSolver), with one rule for order, sign and
// selection wherever offline/ compresses or compares coefficient vectors.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>

#include <Eigen/Core>

namespace vpe::common {

struct PrincipalAxes {
    Eigen::VectorXd mean;       // the samples' mean
    Eigen::MatrixXd axes;       // unit axes as columns, largest variance first; each axis's
                                // largest-magnitude entry is positive, so no axis flips sign
                                // between builds or machines
    Eigen::VectorXd variances;  // the variance along each axis (≥ 0), descending
    double totalVariance = 0;   // the sum over all axes, kept or not
    std::size_t samples = 0;

    int count() const { return static_cast<int>(axes.cols()); }
    // Share of the total variance along the kept axes (0 when there is no variance).
    double explained() const;
};

// Which axes to keep, after sorting by variance: at most maxAxes, and no more than needed
// to explain varianceToKeep of the total (at least one, however little variance there is);
// with dropBelow ≥ 0, no axis whose variance is at most dropBelow × total.
struct AxisSelection {
    int maxAxes = std::numeric_limits<int>::max();
    double varianceToKeep = std::numeric_limits<double>::infinity();  // ∞: maxAxes decides
    double dropBelow = -1.0;  // negative: axes without variance are kept too
};

// Sample i of count, dims values. Called twice per sample (mean, then covariance) so that a
// large mean does not cancel the covariance's precision.
using SampleAt = std::function<const float*(std::size_t i)>;

PrincipalAxes principalAxes(std::size_t count, int dims, const SampleAt& sampleAt,
                            const AxisSelection& selection = {});

}  // namespace vpe::common
