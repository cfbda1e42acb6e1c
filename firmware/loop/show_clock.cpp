// SPDX-License-Identifier: MIT
#include "vpe/firmware/loop/show_clock.h"

#include <ctime>

#include "vpe/firmware/input/input_device.h"

namespace vpe::firmware {

std::int64_t realtimeNowNs() {
    timespec now{};
    ::clock_gettime(CLOCK_REALTIME, &now);
    return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::int64_t ShowClock::nowNs() const {
    return kind_ == Kind::kRealtime ? realtimeNowNs() : monotonicNowNs();
}

std::int64_t ShowClock::fromMonotonic(std::int64_t monotonicNs) const {
    if (kind_ == Kind::kMonotonic) {
        return monotonicNs;
    }
    return monotonicNs + (realtimeNowNs() - monotonicNowNs());
}

std::int64_t ShowClock::toRealtime(std::int64_t showNs) const {
    if (kind_ == Kind::kRealtime) {
        return showNs;
    }
    return showNs + (realtimeNowNs() - monotonicNowNs());
}

}  // namespace vpe::firmware
