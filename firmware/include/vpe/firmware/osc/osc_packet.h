// SPDX-License-Identifier: MIT
// decodeOscPacket: one UDP datagram to the OSC messages it carries, in order. A datagram is a
// message or a bundle ("#bundle", a time tag, then size-prefixed messages and bundles). liblo
// decodes each message (lo_message_deserialise validates the address, the type tags and every
// argument's size); the bundle framing is read here, with every size checked against the
// datagram. Bundles run on arrival: their time tags are ignored (proto/OSC.md).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "vpe/firmware/osc/osc_message.h"

namespace vpe::firmware {

// Deeper nesting than this is refused: a datagram cannot make the decoder recurse without end.
inline constexpr int kMaxOscBundleDepth = 8;

// The messages, or one line saying what is wrong ("bundle element of 4096 bytes overruns the
// 60-byte datagram"). A bundle with any malformed element is refused whole.
using OscPacket = std::variant<std::vector<OscMessage>, std::string>;

OscPacket decodeOscPacket(std::span<const std::uint8_t> datagram);

}  // namespace vpe::firmware
