// SPDX-License-Identifier: MIT
// IdleDrift: where the light goes when nobody steers it: a slow figure of eight over the
// board's idle ranges (azimuth sweeps once, elevation twice per period), entered by blending
// from wherever the light was over the handover time, so the takeover is never a jump.
#pragma once

#include "vpe/firmware/light/light_config.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware {

class IdleDrift {
public:
    explicit IdleDrift(const IdleConfig& config) : config_(config) {}

    // The drift's own path at `seconds` since it began (distance is the caller's).
    SphericalPosition path(double seconds, double distanceM) const;
    // The drift begun at `from`, `seconds` ago: the path blended in with a smoothstep.
    SphericalPosition position(const SphericalPosition& from, double seconds) const;

private:
    IdleConfig config_;
};

}  // namespace vpe::firmware
