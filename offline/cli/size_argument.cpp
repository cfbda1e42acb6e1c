// SPDX-License-Identifier: MIT
#include "cli/size_argument.h"

#include <cstdio>

#include "vpe/common/input_error.h"

namespace vpe::cli {

SizeArgument parseSizeArgument(const std::string& text, const std::string& option, int maxSide) {
    SizeArgument size;
    char separator = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &size.width, &separator, &size.height, &extra) != 3 ||
        (separator != 'x' && separator != 'X') || size.width < 1 || size.height < 1 ||
        size.width > maxSide || size.height > maxSide) {
        throw common::InputError(option + ": '" + text +
                                 "' is not a size WxH (e.g. 1024x1024; sides 1.." +
                                 std::to_string(maxSide) + ")");
    }
    return size;
}

}  // namespace vpe::cli
