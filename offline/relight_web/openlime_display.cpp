// SPDX-License-Identifier: MIT
// OpenLIME's display chain, value by value.
#include "vpe/relight_web/openlime_display.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vpe::relight_web {

namespace {

constexpr double kDisplayGamma = 2.2;

// What an 8-bit offscreen code comes out as on the 8-bit canvas: 256 values.
const std::array<float, 256>& canvasOfOffscreenCode() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> values{};
        for (int code = 0; code < 256; ++code) {
            const double shown = std::pow(code / 255.0, 1.0 / kDisplayGamma);
            values[static_cast<std::size_t>(code)] =
                static_cast<float>(std::round(255.0 * shown) / 255.0);
        }
        return values;
    }();
    return table;
}

}  // namespace

float openLimeDisplayed(float decoded) {
    // A negative (or NaN) value has no defined pow(); it is shown as black.
    if (!(decoded > 0.0f)) {
        return 0.0f;
    }
    const double linear = std::pow(static_cast<double>(decoded), kDisplayGamma);
    // Float to an unsigned normalized 8-bit channel: clamp, scale, round to nearest.
    const long code = std::lround(255.0 * std::min(linear, 1.0));
    return canvasOfOffscreenCode()[static_cast<std::size_t>(code)];
}

void showAsOpenLime(std::vector<float>& values) {
    for (float& value : values) {
        value = openLimeDisplayed(value);
    }
}

}  // namespace vpe::relight_web
