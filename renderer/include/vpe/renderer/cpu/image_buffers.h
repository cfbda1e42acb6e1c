// SPDX-License-Identifier: MIT
// The renderer's output images: row-major, row 0 is the TOP row of the picture (the camera's
// or projector's y grows downwards, OpenCV's convention), pixel (x, y) centred at (x, y).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vpe::renderer {

// Linear float RGB, three values per pixel.
struct RgbImage {
    int width = 0, height = 0;
    std::vector<float> values;  // (y·width + x)·3 + channel

    RgbImage() = default;
    RgbImage(int w, int h) : width(w), height(h), values(pixelCount() * 3, 0.0f) {}

    std::size_t pixelCount() const {
        return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    }
    float* pixel(int x, int y) { return values.data() + offset(x, y) * 3; }
    const float* pixel(int x, int y) const { return values.data() + offset(x, y) * 3; }

private:
    std::size_t offset(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x);
    }
};

// One value per pixel.
template <typename T>
struct ScalarImage {
    int width = 0, height = 0;
    std::vector<T> values;  // y·width + x

    ScalarImage() = default;
    ScalarImage(int w, int h, T fill = T{})
        : width(w),
          height(h),
          values(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

    T& at(int x, int y) { return values[offset(x, y)]; }
    const T& at(int x, int y) const { return values[offset(x, y)]; }

private:
    std::size_t offset(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x);
    }
};

// 1 where a property holds, 0 elsewhere.
using MaskImage = ScalarImage<std::uint8_t>;
using FloatImage = ScalarImage<float>;

}  // namespace vpe::renderer
