// SPDX-License-Identifier: MIT
// Text taken from a file, made safe for a one-line message: control characters (a newline in
// a region name, say) become \xNN. Private to the bundle reader.
#pragma once

#include <string>
#include <string_view>

namespace vpe::proto {

// asciiOnly: escape bytes ≥ 0x80 too (for binary fields such as the magic); otherwise they
// pass through, so that UTF-8 names read as written.
inline std::string printableText(std::string_view text, bool asciiOnly = false) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string printable;
    for (char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20 || byte == 0x7f || byte == '\\' || (asciiOnly && byte >= 0x80)) {
            printable += "\\x";
            printable += kHex[byte >> 4];
            printable += kHex[byte & 15];
        } else {
            printable += c;
        }
    }
    return printable;
}

}  // namespace vpe::proto
