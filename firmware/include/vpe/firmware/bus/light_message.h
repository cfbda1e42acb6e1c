// SPDX-License-Identifier: MIT
// LightMessage: the retained state on vpe/<show>/light, the contract between the nodes of a show
// (proto/BUS.md): JSON, one object, times in microseconds of CLOCK_REALTIME. The reader is
// strict about what it needs (types, finite numbers, the board's light limits) and refuses the
// whole message otherwise: a refused message never moves the light.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "vpe/firmware/board/light_config.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware::bus {

inline constexpr int kLightMessageFormat = 1;
// No state is longer: a bigger payload is refused before it is parsed.
inline constexpr std::size_t kLightMessageMaxBytes = 4096;

struct LightMessage {
    std::string node;          // the publishing node's client id
    std::uint64_t seq = 0;     // per node, from 1, increasing by one per message
    std::int64_t timeUs = 0;   // when the state was made (its newest change)
    SphericalPosition target;  // "azimuth", "elevation", "distance"
    SphericalPosition from;    // "from": the light at fromUs, where the move started
    std::int64_t fromUs = 0;
    std::optional<std::int64_t> driftUs;  // the idle drift takes over; empty (null): never
    std::string preset;                   // the weight preset's name; empty: not said
    std::string source;                   // the input that steered: "knobs", "camera", "osc"
};

std::string encodeLightMessage(const LightMessage& message);

enum class LightMessageProblem : std::uint8_t {
    kMalformed,   // not JSON, not an object, a missing key, a wrong type, another format
    kOutOfRange,  // a number outside the board's light limits or not finite, times out of order
};

struct LightMessageRefusal {
    LightMessageProblem problem = LightMessageProblem::kMalformed;
    std::string reason;  // "azimuth 270 is outside [-100, 100]"
};

// `limits`: the receiving board's (distance resolved). Azimuths wrap when the limits span the
// full circle.
std::variant<LightMessage, LightMessageRefusal> decodeLightMessage(std::string_view payload,
                                                                   const LightLimits& limits);

}  // namespace vpe::firmware::bus
