// SPDX-License-Identifier: MIT
// The sRGB transfer function (IEC 61966-2-1). vpe works in linear radiance inside and uses
// these only at its edges: decoding 8-bit captures and encoding pictures for people.
#pragma once

#include <cmath>

namespace vpe::proto {

inline double srgbToLinear(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

inline double linearToSrgb(double linear) {
    return linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

}  // namespace vpe::proto
