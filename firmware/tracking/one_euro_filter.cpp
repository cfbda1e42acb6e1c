// SPDX-License-Identifier: MIT
// The 1€ filter as in the paper's algorithm: the speed is estimated from the previous
// *filtered* value, smoothed with the derivative cutoff, and sets the value's cutoff.
#include "vpe/firmware/tracking/one_euro_filter.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace vpe::firmware {

OneEuroFilter::OneEuroFilter(const OneEuroParameters& parameters) : parameters_(parameters) {
    if (!(std::isfinite(parameters.minCutoffHz) && parameters.minCutoffHz > 0.0)) {
        throw std::invalid_argument("one euro filter: min cutoff must be positive, got " +
                                    std::to_string(parameters.minCutoffHz));
    }
    if (!(std::isfinite(parameters.beta) && parameters.beta >= 0.0)) {
        throw std::invalid_argument("one euro filter: beta must be ≥ 0, got " +
                                    std::to_string(parameters.beta));
    }
    if (!(std::isfinite(parameters.derivativeCutoffHz) && parameters.derivativeCutoffHz > 0.0)) {
        throw std::invalid_argument("one euro filter: derivative cutoff must be positive, got " +
                                    std::to_string(parameters.derivativeCutoffHz));
    }
}

double OneEuroFilter::smoothingFactor(double dtS, double cutoffHz) {
    const double tau = 1.0 / (2.0 * std::numbers::pi * cutoffHz);
    return 1.0 / (1.0 + tau / dtS);
}

double OneEuroFilter::filter(double value, double timestampS) {
    if (!std::isfinite(value) || !std::isfinite(timestampS)) {
        throw std::invalid_argument("one euro filter: non-finite sample " + std::to_string(value) +
                                    " at " + std::to_string(timestampS) + " s");
    }
    if (!primed_) {
        primed_ = true;
        previousTimeS_ = timestampS;
        previousValue_ = value;
        previousDerivative_ = 0.0;
        return value;
    }
    const double dt = timestampS - previousTimeS_;
    if (!(dt > 0.0)) {
        return previousValue_;
    }
    const double derivative = (value - previousValue_) / dt;
    const double alphaDerivative = smoothingFactor(dt, parameters_.derivativeCutoffHz);
    // α·x + (1 − α)·x̂ written as x̂ + α·(x − x̂): equal, and a constant signal stays exact.
    previousDerivative_ += alphaDerivative * (derivative - previousDerivative_);
    const double cutoff =
        parameters_.minCutoffHz + parameters_.beta * std::abs(previousDerivative_);
    const double alpha = smoothingFactor(dt, cutoff);
    previousValue_ += alpha * (value - previousValue_);
    previousTimeS_ = timestampS;
    return previousValue_;
}

}  // namespace vpe::firmware
