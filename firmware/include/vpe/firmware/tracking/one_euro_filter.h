// SPDX-License-Identifier: MIT
// OneEuroFilter: the 1€ filter (Casiez, Roussel and Vogel, CHI 2012), a first-order low-pass
// whose cutoff rises with the signal's speed: at rest a low cutoff removes jitter, in motion a
// higher one removes lag. Timestamps in seconds at any (variable) rate. One filter smooths one
// coordinate; the lamp tracker runs one per image axis.
#pragma once

namespace vpe::firmware {

struct OneEuroParameters {
    double minCutoffHz = 1.0;  // cutoff at rest (> 0)
    // Cutoff increase per unit of speed (≥ 0): Hz per (signal unit / s), e.g. per px/s.
    double beta = 0.05;
    double derivativeCutoffHz = 1.0;  // cutoff of the speed estimate (> 0)
};

class OneEuroFilter {
public:
    // Throws std::invalid_argument for non-finite or out-of-range parameters.
    explicit OneEuroFilter(const OneEuroParameters& parameters = {});

    // The filtered value of `value` sampled at `timestampS`. The first sample after
    // construction or reset() passes through unchanged. A timestamp not after the previous one
    // carries no time step to filter over: the previous output is returned and the state kept.
    // Throws std::invalid_argument for a non-finite value or timestamp.
    double filter(double value, double timestampS);

    // Forget the history: the next sample passes through (the lamp was lost and found again
    // elsewhere; smoothing from its stale position would sweep the light across the room).
    void reset() { primed_ = false; }

    bool primed() const { return primed_; }
    const OneEuroParameters& parameters() const { return parameters_; }

    // The exponential smoothing factor of a first-order low-pass with cutoff `cutoffHz` over a
    // step `dtS`: α = 1 / (1 + τ/Te), τ = 1 / (2π fc), Te = dt.
    static double smoothingFactor(double dtS, double cutoffHz);

private:
    OneEuroParameters parameters_;
    bool primed_ = false;
    double previousTimeS_ = 0.0;
    double previousValue_ = 0.0;       // the previous output x̂
    double previousDerivative_ = 0.0;  // the previous smoothed speed dx̂
};

}  // namespace vpe::firmware
