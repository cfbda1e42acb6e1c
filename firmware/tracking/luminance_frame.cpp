// SPDX-License-Identifier: MIT
#include "vpe/firmware/tracking/luminance_frame.h"

#include <stdexcept>
#include <string>

namespace vpe::firmware {

void checkLuminanceView(const LuminanceView& view) {
    const std::string name = "luminance frame " + std::to_string(view.width) + "x" +
                             std::to_string(view.height) + " stride " + std::to_string(view.stride);
    if (view.width <= 0 || view.height <= 0) {
        throw std::invalid_argument(name + ": empty");
    }
    if (view.stride < view.width) {
        throw std::invalid_argument(name + ": stride below width");
    }
    const auto needed =
        static_cast<std::size_t>(view.stride) * static_cast<std::size_t>(view.height - 1) +
        static_cast<std::size_t>(view.width);
    if (view.bytes.data() == nullptr || view.bytes.size() < needed) {
        throw std::invalid_argument(name + ": " + std::to_string(view.bytes.size()) +
                                    " bytes, needs " + std::to_string(needed));
    }
}

}  // namespace vpe::firmware
