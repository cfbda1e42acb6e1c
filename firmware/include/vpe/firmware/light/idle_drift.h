// SPDX-License-Identifier: MIT
// IdleDrift: where the light goes when nobody steers it: a slow figure of eight over the
// board's idle ranges (azimuth sweeps once, elevation twice per period), entered by blending
// from wherever the light was over the handover time, so the takeover is never a jump. The
// path is a function of the clock alone (its phase is the time modulo the period), so that
// nodes sharing a clock draw the same drift without telling each other.
#pragma once

#include <cstdint>

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware {

class IdleDrift {
public:
    explicit IdleDrift(const IdleConfig& config) : config_(config) {}

    // The path at phase `seconds` (0: the ranges' centres, heading right and up); distance is
    // the caller's.
    SphericalPosition path(double seconds, double distanceM) const;
    // The path's phase at clock time `nowNs`: the time modulo the period, in seconds.
    double phaseAt(std::int64_t nowNs) const;
    // The drift begun at `from`, `sinceStart` seconds ago, now at phase `pathSeconds`: the path
    // blended in with a smoothstep over the handover time.
    SphericalPosition position(const SphericalPosition& from, double sinceStart,
                               double pathSeconds) const;

private:
    IdleConfig config_;
};

}  // namespace vpe::firmware
