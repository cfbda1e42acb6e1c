// SPDX-License-Identifier: MIT
// FlooredProjection: a pixel's PCA coefficients by least squares, kept so that the values they
// decode to at every light-grid node stay above a floor (OpenLIME takes pow() of them).
#pragma once

#include <Eigen/Dense>

namespace vpe::relight_web {

class FlooredProjection {
public:
    // `basis`: one column per plane, one row per decoded value (grid node × colour).
    explicit FlooredProjection(const Eigen::MatrixXd& basis);

    // The coefficients r minimizing ‖basis·r − target‖² subject to basis·r ≥ floor and, where
    // given (non-empty), lo ≤ r ≤ hi. r = 0 must satisfy them (floor ≤ 0, lo ≤ 0 ≤ hi): the
    // search starts there and never leaves the constraints, so even when it stops early
    // (kMaxSteps, a degenerate corner) the answer keeps every floor. Constraints within
    // kTolerance count as kept.
    Eigen::VectorXd solve(const Eigen::VectorXd& target, const Eigen::VectorXd& floor,
                          const Eigen::VectorXd& lo = {}, const Eigen::VectorXd& hi = {}) const;

    static constexpr int kMaxSteps = 400;
    static constexpr double kTolerance = 1e-12;

private:
    Eigen::MatrixXd basis_;
    Eigen::MatrixXd gram_;  // basisᵀ·basis
    Eigen::LDLT<Eigen::MatrixXd> gramSolver_;
};

}  // namespace vpe::relight_web
