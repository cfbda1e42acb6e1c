// SPDX-License-Identifier: MIT
// ShowClock: the clock the light rig runs on. CLOCK_MONOTONIC for a node alone: it never jumps.
// CLOCK_REALTIME for a node of a multi-node show (firmware/bus/): the one clock the nodes share,
// kept together by chrony (docs/multi-node.md), so that the light's moves and the idle drift
// are the same function of time on every node. Inputs stamp their events on CLOCK_MONOTONIC
// (GPIO edges, camera exposures, datagram arrivals); fromMonotonic converts.
#pragma once

#include <cstdint>

namespace vpe::firmware {

class ShowClock {
public:
    enum class Kind { kMonotonic, kRealtime };

    explicit ShowClock(Kind kind = Kind::kMonotonic) : kind_(kind) {}

    Kind kind() const { return kind_; }
    bool shared() const { return kind_ == Kind::kRealtime; }
    std::int64_t nowNs() const;
    // A CLOCK_MONOTONIC time on this clock (the offset between the clocks read now: a step of
    // the wall clock moves later conversions with it).
    std::int64_t fromMonotonic(std::int64_t monotonicNs) const;
    // A time of this clock on CLOCK_REALTIME (for logs other nodes' logs are compared with).
    std::int64_t toRealtime(std::int64_t showNs) const;

private:
    Kind kind_;
};

// CLOCK_REALTIME in nanoseconds since the epoch.
std::int64_t realtimeNowNs();

}  // namespace vpe::firmware
