// SPDX-License-Identifier: MIT
// InputSource: where a light event came from. The light rig lets the last active source win
// and reports it (the player's --json `light.active`, OSC's /vpe/status reply).
#pragma once

#include <cstdint>

namespace vpe::firmware {

// kIdle is the rig's own drift, never an input's. kBus is another node's light, received over
// the show's MQTT broker (firmware/bus/, proto/BUS.md).
enum class InputSource : std::uint8_t { kKnobs, kCamera, kOsc, kIdle, kBus };

// "knobs", "camera", "osc", "idle", "bus".
inline const char* inputSourceName(InputSource source) {
    switch (source) {
        case InputSource::kKnobs:
            return "knobs";
        case InputSource::kCamera:
            return "camera";
        case InputSource::kOsc:
            return "osc";
        case InputSource::kIdle:
            return "idle";
        case InputSource::kBus:
            return "bus";
    }
    return "unknown";
}

}  // namespace vpe::firmware
