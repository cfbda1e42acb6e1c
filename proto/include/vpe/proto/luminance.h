// SPDX-License-Identifier: MIT
// Rec. 709 luminance of linear RGB: what a monochrome sensor integrates, and the grey of a colour
// picture for the scan's decoder and the calibration's corner detector.
#pragma once

namespace vpe::proto {

// The weights of R, G and B, for sums over other types (a colour's transport vectors).
inline constexpr double kLuminance709[3] = {0.2126, 0.7152, 0.0722};

constexpr double luminance709(double r, double g, double b) {
    return kLuminance709[0] * r + kLuminance709[1] * g + kLuminance709[2] * b;
}

// The same in single precision, for images kept in float (a camera frame, a weight source):
// the sum a float expression of these constants gives.
constexpr float luminance709f(float r, float g, float b) {
    return static_cast<float>(kLuminance709[0]) * r + static_cast<float>(kLuminance709[1]) * g +
           static_cast<float>(kLuminance709[2]) * b;
}

}  // namespace vpe::proto
