// SPDX-License-Identifier: MIT
// LampCalibration: least squares through the normal equations, solved by Gaussian elimination
// with partial pivoting (at most 6 × 6; the device has no linear-algebra library). Positions
// are centred and scaled first, so the monomials are all of order 1 and a small pivot means a
// degenerate point set, not large pixel numbers.
#include "vpe/firmware/tracking/lamp_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace vpe::firmware {

namespace {

constexpr std::size_t kMaxTerms = 6;
// Below this ratio of the smallest elimination pivot to the normal matrix's largest diagonal
// entry the fit is refused: its reciprocal condition number is about the square of the design
// matrix's, so this admits a design condition number up to 10⁴.
constexpr double kMinPivotRatio = 1e-8;

// Solves N c = b for two right-hand sides (azimuth, elevation) in place; false when a pivot is
// too small relative to N's largest diagonal entry.
bool solve(std::array<std::array<double, kMaxTerms + 2>, kMaxTerms>& augmented, std::size_t terms) {
    double largestDiagonal = 0.0;
    for (std::size_t i = 0; i < terms; ++i) {
        largestDiagonal = std::max(largestDiagonal, std::abs(augmented[i][i]));
    }
    if (!(largestDiagonal > 0.0)) {
        return false;
    }
    const std::size_t columns = terms + 2;
    for (std::size_t pivot = 0; pivot < terms; ++pivot) {
        std::size_t best = pivot;
        for (std::size_t row = pivot + 1; row < terms; ++row) {
            if (std::abs(augmented[row][pivot]) > std::abs(augmented[best][pivot])) {
                best = row;
            }
        }
        if (std::abs(augmented[best][pivot]) < kMinPivotRatio * largestDiagonal) {
            return false;
        }
        std::swap(augmented[pivot], augmented[best]);
        for (std::size_t row = pivot + 1; row < terms; ++row) {
            const double factor = augmented[row][pivot] / augmented[pivot][pivot];
            for (std::size_t column = pivot; column < columns; ++column) {
                augmented[row][column] -= factor * augmented[pivot][column];
            }
        }
    }
    for (std::size_t rhs = terms; rhs < columns; ++rhs) {
        for (std::size_t row = terms; row-- > 0;) {
            double sum = augmented[row][rhs];
            for (std::size_t column = row + 1; column < terms; ++column) {
                sum -= augmented[row][column] * augmented[column][rhs];
            }
            augmented[row][rhs] = sum / augmented[row][row];
        }
    }
    return true;
}

}  // namespace

std::array<double, 6> LampCalibration::monomials(double u, double v) const {
    const double s = (u - centreU_) * inverseScale_;
    const double t = (v - centreV_) * inverseScale_;
    return {1.0, s, t, s * s, s * t, t * t};
}

LampCalibration LampCalibration::fit(std::span<const CalibrationPoint> points) {
    if (points.size() < 3) {
        throw CalibrationError("needs at least 3 points [u, v, azimuth_deg, elevation_deg], got " +
                               std::to_string(points.size()));
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
        const CalibrationPoint& p = points[i];
        if (!std::isfinite(p.u) || !std::isfinite(p.v) || !std::isfinite(p.azimuthDeg) ||
            !std::isfinite(p.elevationDeg)) {
            throw CalibrationError("point " + std::to_string(i) + " has a non-finite value");
        }
    }

    LampCalibration calibration;
    calibration.model_ = points.size() >= 6 ? Model::kQuadratic : Model::kAffine;
    const std::size_t terms = calibration.model_ == Model::kQuadratic ? 6 : 3;
    const auto count = static_cast<double>(points.size());

    for (const CalibrationPoint& p : points) {
        calibration.centreU_ += p.u / count;
        calibration.centreV_ += p.v / count;
    }
    double meanSquareRadius = 0.0;
    for (const CalibrationPoint& p : points) {
        const double du = p.u - calibration.centreU_;
        const double dv = p.v - calibration.centreV_;
        meanSquareRadius += (du * du + dv * dv) / count;
    }
    if (!(meanSquareRadius > 0.0)) {
        throw CalibrationError("all " + std::to_string(points.size()) +
                               " points are at the same image position");
    }
    calibration.inverseScale_ = 1.0 / std::sqrt(meanSquareRadius);

    std::array<std::array<double, kMaxTerms + 2>, kMaxTerms> augmented{};
    for (const CalibrationPoint& p : points) {
        const std::array<double, 6> m = calibration.monomials(p.u, p.v);
        for (std::size_t i = 0; i < terms; ++i) {
            for (std::size_t j = 0; j < terms; ++j) {
                augmented[i][j] += m[i] * m[j];
            }
            augmented[i][terms] += m[i] * p.azimuthDeg;
            augmented[i][terms + 1] += m[i] * p.elevationDeg;
        }
    }
    if (!solve(augmented, terms)) {
        if (calibration.model_ == Model::kAffine) {
            throw CalibrationError(
                "the " + std::to_string(points.size()) +
                " points lie on (nearly) one line: an affine map needs 3 points not in a line");
        }
        throw CalibrationError("the " + std::to_string(points.size()) +
                               " points lie on (nearly) one conic (a circle, an ellipse, two "
                               "lines): a quadratic map needs points off it, e.g. one at the "
                               "centre");
    }
    for (std::size_t i = 0; i < terms; ++i) {
        calibration.azimuth_[i] = augmented[i][terms];
        calibration.elevation_[i] = augmented[i][terms + 1];
    }

    double squaredError = 0.0;
    for (const CalibrationPoint& p : points) {
        const LightDirection fitted = calibration.direction(p.u, p.v);
        const double da = fitted.azimuthDeg - p.azimuthDeg;
        const double de = fitted.elevationDeg - p.elevationDeg;
        squaredError += da * da + de * de;
    }
    calibration.rmsResidualDeg_ = std::sqrt(squaredError / count);
    return calibration;
}

LightDirection LampCalibration::direction(double u, double v) const {
    const std::array<double, 6> m = monomials(u, v);
    LightDirection direction;
    for (std::size_t i = 0; i < m.size(); ++i) {
        // The affine model's quadratic coefficients are zero.
        direction.azimuthDeg += azimuth_[i] * m[i];
        direction.elevationDeg += elevation_[i] * m[i];
    }
    return direction;
}

}  // namespace vpe::firmware
