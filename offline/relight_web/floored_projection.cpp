// SPDX-License-Identifier: MIT
// A small primal active-set method for least squares under lower bounds.
#include "vpe/relight_web/floored_projection.h"

#include <algorithm>
#include <vector>

namespace vpe::relight_web {

FlooredProjection::FlooredProjection(const Eigen::MatrixXd& basis)
    : basis_(basis), gram_(basis.transpose() * basis), gramSolver_(gram_) {}

Eigen::VectorXd FlooredProjection::solve(const Eigen::VectorXd& target,
                                         const Eigen::VectorXd& floor, const Eigen::VectorXd& lo,
                                         const Eigen::VectorXd& hi) const {
    const Eigen::Index planes = basis_.cols();
    const Eigen::Index values = basis_.rows();
    const bool boxed = lo.size() == planes && hi.size() == planes;
    // Constraint i: a_i·r ≥ b_i; rows of the basis, then r_k ≥ lo_k and −r_k ≥ −hi_k.
    const Eigen::Index constraints = values + (boxed ? 2 * planes : 0);
    const auto row = [&](Eigen::Index i) -> Eigen::VectorXd {
        if (i < values) {
            return basis_.row(i).transpose();
        }
        const Eigen::Index k = (i - values) % planes;
        return (i - values < planes ? 1.0 : -1.0) * Eigen::VectorXd::Unit(planes, k);
    };
    const auto bound = [&](Eigen::Index i) {
        if (i < values) {
            return floor(i);
        }
        const Eigen::Index k = (i - values) % planes;
        return i - values < planes ? lo(k) : -hi(k);
    };
    const Eigen::VectorXd gradientAtZero = -(basis_.transpose() * target);

    // Most pixels: the plain least-squares answer already keeps every floor.
    Eigen::VectorXd r = gramSolver_.solve(-gradientAtZero);
    {
        const Eigen::VectorXd decoded = basis_ * r;
        bool kept = (decoded - floor).minCoeff() >= -kTolerance;
        if (boxed) {
            kept = kept && (r - lo).minCoeff() >= -kTolerance && (hi - r).minCoeff() >= -kTolerance;
        }
        if (kept) {
            return r;
        }
    }

    // Otherwise walk from r = 0 (feasible by the caller's word), keeping a working set of
    // constraints held as equalities (Nocedal & Wright, Numerical Optimization, §16.5).
    r = Eigen::VectorXd::Zero(planes);
    std::vector<Eigen::Index> working;
    for (int step = 0; step < kMaxSteps; ++step) {
        const Eigen::VectorXd gradient = gram_ * r + gradientAtZero;
        Eigen::MatrixXd active(planes, static_cast<Eigen::Index>(working.size()));
        for (std::size_t j = 0; j < working.size(); ++j) {
            active.col(static_cast<Eigen::Index>(j)) = row(working[j]);
        }
        // The best step within the working set's null space.
        Eigen::VectorXd move = Eigen::VectorXd::Zero(planes);
        if (static_cast<Eigen::Index>(working.size()) < planes) {
            Eigen::MatrixXd free;
            if (working.empty()) {
                free = Eigen::MatrixXd::Identity(planes, planes);
            } else {
                const Eigen::HouseholderQR<Eigen::MatrixXd> qr(active);
                const Eigen::MatrixXd q = qr.householderQ();
                free = q.rightCols(planes - static_cast<Eigen::Index>(working.size()));
            }
            const Eigen::MatrixXd reduced = free.transpose() * gram_ * free;
            move = -free * reduced.ldlt().solve(free.transpose() * gradient);
        }
        if (move.norm() <= 1e-12 * (1.0 + r.norm())) {
            // At the working set's minimum: done unless a constraint pulls the wrong way.
            if (working.empty()) {
                return r;
            }
            const Eigen::VectorXd multipliers = active.colPivHouseholderQr().solve(gradient);
            Eigen::Index leaving = 0;
            const double lowest = multipliers.minCoeff(&leaving);
            if (lowest >= -1e-12) {
                return r;
            }
            working.erase(working.begin() + leaving);
            continue;
        }
        // Go as far along the step as the constraints outside the working set allow.
        double length = 1.0;
        Eigen::Index blocking = -1;
        for (Eigen::Index i = 0; i < constraints; ++i) {
            if (std::find(working.begin(), working.end(), i) != working.end()) {
                continue;
            }
            const Eigen::VectorXd a = row(i);
            const double along = a.dot(move);
            if (along >= -1e-15) {
                continue;
            }
            const double room = std::max(0.0, a.dot(r) - bound(i));
            if (room / -along < length) {
                length = room / -along;
                blocking = i;
            }
        }
        r += length * move;
        if (blocking >= 0) {
            working.push_back(blocking);
        }
    }
    return r;
}

}  // namespace vpe::relight_web
