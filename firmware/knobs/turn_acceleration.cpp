// SPDX-License-Identifier: MIT
// Turn acceleration: the linear ramp between slowMs and fastMs.
#include "vpe/firmware/knobs/turn_acceleration.h"

namespace vpe::firmware::knobs {

double accelerationFactor(const AccelerationCurve& curve, double intervalMs) {
    if (!(curve.maxFactor > 1) || !(intervalMs < curve.slowMs)) {
        return 1;
    }
    if (intervalMs <= curve.fastMs || !(curve.slowMs > curve.fastMs)) {
        return curve.maxFactor;
    }
    const double t = (curve.slowMs - intervalMs) / (curve.slowMs - curve.fastMs);
    return 1 + (curve.maxFactor - 1) * t;
}

double TurnAccelerator::factorFor(int direction, std::int64_t timestampNs) {
    double factor = 1;
    if (direction == lastDirection_) {
        // Edges can arrive out of order by a hair across lines; a negative interval is "fast".
        const double intervalMs = static_cast<double>(timestampNs - lastNs_) / 1e6;
        factor = accelerationFactor(curve_, intervalMs);
    }
    lastDirection_ = direction;
    lastNs_ = timestampNs;
    return factor;
}

}  // namespace vpe::firmware::knobs
