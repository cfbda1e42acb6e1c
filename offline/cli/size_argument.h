// SPDX-License-Identifier: MIT
// The WxH arguments of several commands (--size, --projector-size, --view-size).
#pragma once

#include <string>

namespace vpe::cli {

struct SizeArgument {
    int width = 0;
    int height = 0;
};

// "1024x768" (or 1024X768) → {1024, 768}; each side 1..maxSide. Throws InputError naming the
// option and the text otherwise.
SizeArgument parseSizeArgument(const std::string& text, const std::string& option,
                               int maxSide = 16384);

}  // namespace vpe::cli
