// SPDX-License-Identifier: MIT
#include "vpe/firmware/osc/osc_message.h"

#include <cstdio>

namespace vpe::firmware {

namespace {

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};
// Clang 14 (the fuzz build) has no aggregate deduction yet: the guide C++17 needed.
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace

char oscTypeTag(const OscArgument& argument) {
    return std::visit(Overloaded{[](std::int32_t) { return 'i'; }, [](std::int64_t) { return 'h'; },
                                 [](float) { return 'f'; }, [](double) { return 'd'; },
                                 [](const std::string&) { return 's'; },
                                 [](const OscOtherArgument& other) { return other.typeTag; }},
                      argument);
}

std::string oscTypeTags(std::span<const OscArgument> arguments) {
    std::string tags;
    tags.reserve(arguments.size());
    for (const OscArgument& argument : arguments) {
        tags += oscTypeTag(argument);
    }
    return tags;
}

std::string printableOscText(const std::string& text, std::size_t limit) {
    std::string out;
    for (const char c : text) {
        if (out.size() >= limit) {
            out += "…";
            break;
        }
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte < 0x7f && c != '\\') {
            out += c;
        } else {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
            out += escaped;
        }
    }
    return out;
}

}  // namespace vpe::firmware
