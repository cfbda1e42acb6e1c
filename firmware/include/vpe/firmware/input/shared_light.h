// SPDX-License-Identifier: MIT
// SharedLight: the light rig's state as the nodes of one show share it (firmware/bus/,
// proto/BUS.md). It determines the light at any later time on every node alike: the light moves
// from `from` (where it was at moveStartNs) toward `target` with the board's smoothing time
// constant, and from driftAtNs on the idle drift takes over, whose figure of eight is a
// function of the shared clock. Times are on the rig's clock (CLOCK_REALTIME when a bus is
// configured: chrony keeps the nodes' clocks together).
#pragma once

#include <cstdint>
#include <optional>

#include "vpe/firmware/input/input_source.h"
#include "vpe/firmware/input/spherical_position.h"

namespace vpe::firmware {

struct SharedLight {
    SphericalPosition from;    // the light at moveStartNs
    SphericalPosition target;  // where it is heading
    std::int64_t moveStartNs = 0;
    // The idle drift takes over at this time, blending in from where the move had brought the
    // light; empty: never (the idle drift is off on the node that steered).
    std::optional<std::int64_t> driftAtNs;
    int preset = -1;  // an index into the bundle's presets; −1: each node keeps its own
    // When this state was made (its newest change: a move, a preset, a release). A node takes
    // another's state only when it is newer than its own.
    std::int64_t revisionNs = 0;
    InputSource steeredBy = InputSource::kIdle;  // the input that made it, on the node that did
};

}  // namespace vpe::firmware
