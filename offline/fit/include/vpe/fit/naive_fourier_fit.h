// SPDX-License-Identifier: MIT
// The textbook per-pixel fit: build A (N × (2M+2)), form AᵀWA + λR, factor with LDLT. Slow,
// obviously right: the oracle for tests and the baseline of the fitting benchmark.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "vpe/proto/reflection_geometry.h"

namespace vpe::fit {

struct NaiveFitResult {
    Eigen::MatrixX3d coefficients;  // (2M+2) × RGB
    bool valid = false;
};

// One pixel: its per-sample angles, normalized RGB observations and weights (0 drops one).
NaiveFitResult fitPixelNaive(const std::vector<proto::ReflectionAngles<double>>& angles,
                             const Eigen::MatrixX3d& observations, const Eigen::VectorXd& weights,
                             int harmonics, double lambda);

}  // namespace vpe::fit
