// SPDX-License-Identifier: MIT
// The light's limits the bus tests decode messages against: azimuth ±100°, elevation 5–80°,
// distance 0.3–1.5 m, so that a test can step outside each.
#pragma once

#include <utility>

#include "vpe/firmware/bus/light_message.h"

namespace vpe::firmware::bus::testing {

inline LightLimits busTestLimits() {
    LightLimits l;
    l.azimuthDeg = {-100, 100};
    l.elevationDeg = {5, 80};
    l.distanceM = std::pair{0.3, 1.5};
    return l;
}

}  // namespace vpe::firmware::bus::testing
