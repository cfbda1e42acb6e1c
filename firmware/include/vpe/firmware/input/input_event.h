// SPDX-License-Identifier: MIT
// InputEvent: what every input (GPIO knobs, the tracked lamp, OSC, replay) hands the light rig.
// Inputs only decode; the rig (firmware/light/) owns the light's state, limits and smoothing,
// and lets the last active source win.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <variant>

namespace vpe::firmware {

// Where an event came from. kIdle is the rig's own drift, never an input's.
enum class InputSource : std::uint8_t { kKnobs, kCamera, kOsc, kIdle };

const char* inputSourceName(InputSource source);

// A relative move on the light's sphere (knobs): degrees, metres.
struct TurnLight {
    double azimuthDeg = 0;
    double elevationDeg = 0;
    double distanceM = 0;
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

using LightAction =
    std::variant<TurnLight, AimLight, PlaceLight, SelectPreset, ResetLight, ReleaseLight>;

struct InputEvent {
    InputSource source = InputSource::kKnobs;
    // CLOCK_MONOTONIC nanoseconds of the physical event (GPIO edge, camera exposure, OSC
    // arrival): latency is measured from here to the frame that shows it.
    std::int64_t timestampNs = 0;
    LightAction action;
};

}  // namespace vpe::firmware
