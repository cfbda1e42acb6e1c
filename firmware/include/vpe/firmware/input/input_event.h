// SPDX-License-Identifier: MIT
// InputEvent: what every input (GPIO knobs, the tracked lamp, OSC, replay, another node over the
// bus) hands the light rig. Inputs only decode; the rig (firmware/light/) owns the light's state,
// limits and smoothing, and lets the last active source win.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <variant>

#include "vpe/firmware/input/input_source.h"
#include "vpe/firmware/input/shared_light.h"

namespace vpe::firmware {

// A relative move on the light's sphere (knobs): degrees, metres.
struct TurnLight {
    double azimuthDeg = 0, elevationDeg = 0, distanceM = 0;
};

// An absolute aim on the sphere (camera, OSC); unset fields keep their value.
struct AimLight {
    std::optional<double> azimuthDeg, elevationDeg, distanceM;
};

// An absolute position in the bundle's object frame, metres (OSC /vpe/light/position). The rig
// converts it to its sphere and clamps it to the board's limits.
struct PlaceLight {
    std::array<double, 3> position{};
};

// A weight-map preset: an index into the bundle's presets, or a step (+1/−1, wrapping).
struct SelectPreset {
    int value = 0;
    bool relative = false;
};

// Back to the board's initial light.
struct ResetLight {};

// The source stopped steering (the lamp was lost beyond its hold time): the light holds, and
// the idle loop's quiet time starts counting.
struct ReleaseLight {};

// Another node's light (firmware/bus/): taken whole when it is newer than this node's, so that
// every node computes the same light from then on.
struct FollowLight {
    SharedLight state;
};

using LightAction = std::variant<TurnLight, AimLight, PlaceLight, SelectPreset, ResetLight,
                                 ReleaseLight, FollowLight>;

struct InputEvent {
    InputSource source = InputSource::kKnobs;
    // CLOCK_MONOTONIC nanoseconds of the physical event (GPIO edge, camera exposure, OSC
    // arrival): latency is measured from here to the frame that shows it.
    std::int64_t timestampNs = 0;
    LightAction action;
};

}  // namespace vpe::firmware
