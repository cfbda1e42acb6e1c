// SPDX-License-Identifier: MIT
// 8-bit luminance images: the Y plane of a YUV420/NV12 camera buffer or a GREY (R8) frame,
// borrowed (LuminanceView) or owned (LuminanceFrame). Pixel (col, row) has its centre at the
// integer coordinates (col, row); every position in tracking/ uses that convention.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vpe::firmware {

// A borrowed frame: `height` rows of `width` bytes, `stride` bytes apart. The last row need
// not be padded, so `bytes` holds at least stride × (height − 1) + width bytes.
struct LuminanceView {
    int width = 0;
    int height = 0;
    int stride = 0;
    std::span<const std::uint8_t> bytes;

    const std::uint8_t* row(int y) const {
        return bytes.data() + static_cast<std::ptrdiff_t>(y) * stride;
    }
};

// Throws std::invalid_argument, one line naming the geometry ("luminance frame 320x240 stride
// 320: 1000 bytes, needs 76800"), when the view is empty, its stride is below its width or its
// bytes cannot hold it. Camera buffers come from a driver: their sizes are checked, not trusted.
void checkLuminanceView(const LuminanceView& view);

// An owned frame with stride = width (synthetic frames, copies).
struct LuminanceFrame {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // row-major, width × height

    LuminanceView view() const { return {width, height, width, pixels}; }
};

}  // namespace vpe::firmware
