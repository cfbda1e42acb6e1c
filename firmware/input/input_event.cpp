// SPDX-License-Identifier: MIT
#include "vpe/firmware/input/input_event.h"

#include <ctime>

#include "vpe/firmware/input/input_device.h"

namespace vpe::firmware {

const char* inputSourceName(InputSource source) {
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

std::int64_t monotonicNowNs() {
    timespec now{};
    ::clock_gettime(CLOCK_MONOTONIC, &now);
    return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

}  // namespace vpe::firmware
