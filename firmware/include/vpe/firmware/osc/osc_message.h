// SPDX-License-Identifier: MIT
// OscMessage: one OSC message as plain values (address, arguments), the form both the socket
// (OscServer, decoded by liblo) and a replay file ({"type":"osc","path":…,"args":[30.0]}) hand to
// the OscDispatcher. No liblo and no JSON library here: a replay reader builds these directly.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace vpe::firmware {

// An argument of a type the address space never takes (blob 'b', true 'T', nil 'N', …): kept
// as its type tag so that the dispatcher can refuse it by name.
struct OscOtherArgument {
    char typeTag = '?';
    bool operator==(const OscOtherArgument&) const = default;
};

// OSC 'i', 'h', 'f', 'd' and 's' (a symbol 'S' arrives as a string). A JSON number maps to
// int64_t when integral, double otherwise; a JSON string to std::string.
using OscArgument =
    std::variant<std::int32_t, std::int64_t, float, double, std::string, OscOtherArgument>;

struct OscMessage {
    std::string path;
    std::vector<OscArgument> arguments;
};

// 'i', 'h', 'f', 'd', 's', or the other argument's own tag.
char oscTypeTag(const OscArgument& argument);

// The type tags of `arguments` without the leading ',': "ff", "" for none.
std::string oscTypeTags(std::span<const OscArgument> arguments);

// For logs: printable ASCII kept, anything else as \xNN, cut to `limit` characters with "…".
// Addresses come off the network, so they never reach the journal raw.
std::string printableOscText(const std::string& text, std::size_t limit = 64);

}  // namespace vpe::firmware
