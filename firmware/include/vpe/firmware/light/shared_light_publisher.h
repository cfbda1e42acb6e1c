// SPDX-License-Identifier: MIT
// SharedLightPublisher: where the player hands the light rig's state after this node's own
// inputs changed it, for the other nodes of the show (firmware/bus/'s LightBus).
#pragma once

#include <cstdint>

#include "vpe/firmware/input/shared_light.h"

namespace vpe::firmware {

class SharedLightPublisher {
public:
    virtual ~SharedLightPublisher() = default;
    // The newest state; the publisher sends at its own pace, and the newest offered is always
    // the one sent last. `nowNs`: CLOCK_MONOTONIC.
    virtual void offer(const SharedLight& state, std::int64_t nowNs) = 0;
};

}  // namespace vpe::firmware
