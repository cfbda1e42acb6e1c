// SPDX-License-Identifier: MIT
// Turn acceleration: a fast spin of a knob moves the light further per detent, so that a slow
// turn still places it precisely and a quick one crosses the sphere in a few turns.
#pragma once

#include <cstdint>

namespace vpe::firmware::knobs {

// Detents further apart than slowMs move one step; closer than fastMs, maxFactor steps; in
// between the factor ramps linearly. maxFactor = 1 turns acceleration off.
struct AccelerationCurve {
    double slowMs = 120;
    double fastMs = 30;
    double maxFactor = 1;
};

// The step factor for a detent `intervalMs` after the previous one (pure).
double accelerationFactor(const AccelerationCurve& curve, double intervalMs);

// Applies the curve to a knob's detents: the interval is measured from the previous detent in
// the same direction; the first detent and a reversal always move one step.
class TurnAccelerator {
public:
    explicit TurnAccelerator(const AccelerationCurve& curve) : curve_(curve) {}

    double factorFor(int direction, std::int64_t timestampNs);

private:
    AccelerationCurve curve_;
    int lastDirection_ = 0;  // 0: no detent yet
    std::int64_t lastNs_ = 0;
};

}  // namespace vpe::firmware::knobs
