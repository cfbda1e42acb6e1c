// SPDX-License-Identifier: MIT
// What every command and switch message on the bus starts with (proto/BUS.md): a JSON object of
// at most kLightMessageMaxBytes with its "format", the sending "node" and a wall-clock
// "time_us". Decoded once here for the blackout and the install commands, with the refusals
// worded once.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "vpe/firmware/bus/light_message.h"

namespace vpe::firmware::bus {

struct MessageEnvelope {
    nlohmann::json body;      // the whole object, for the fields of the message's own
    std::string node;         // 1-64 bytes
    std::int64_t timeUs = 0;  // a wall-clock time in microseconds (2001 to 2100)
};

// The envelope of a message of `format`, or why it is refused (kMalformed or kOutOfRange).
std::variant<MessageEnvelope, LightMessageRefusal> decodeMessageEnvelope(std::string_view payload,
                                                                         int format);

}  // namespace vpe::firmware::bus
