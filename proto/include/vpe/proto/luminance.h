// SPDX-License-Identifier: MIT
// Rec. 709 luminance of linear RGB: what a monochrome sensor integrates, and the grey of a colour
// picture for the scan's decoder and the calibration's corner detector.
#pragma once

namespace vpe::proto {

constexpr double luminance709(double r, double g, double b) {
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

}  // namespace vpe::proto
