// SPDX-License-Identifier: MIT
// SampleBand: a band of rows from every image of a capture in linear radiance, laid out
// planar ([image][channel][row][x]) so that the fitter loads kLanes neighbouring pixels of
// one sample with one vector load. Rows are padded to a multiple of the lane count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vpe {

struct SampleBand {
    static constexpr int kChannels = 3;
    static constexpr int kRowAlignment = 16;

    int width = 0;
    int paddedWidth = 0;
    int rowBegin = 0;
    int rows = 0;
    int images = 0;
    std::vector<float> values;            // [image][channel][row][paddedWidth]
    std::vector<float> weights;           // [image][row][paddedWidth]: 1 usable, 0 not
    std::vector<std::uint8_t> saturated;  // [image][row][paddedWidth]: a channel hit full scale

    void resize(int imageCount, int imageWidth, int rowCount) {
        images = imageCount;
        width = imageWidth;
        paddedWidth = (imageWidth + kRowAlignment - 1) / kRowAlignment * kRowAlignment;
        rows = rowCount;
        const std::size_t plane = static_cast<std::size_t>(rows) * paddedWidth;
        values.assign(plane * kChannels * images, 0.0f);
        weights.assign(plane * images, 0.0f);
        saturated.assign(plane * images, 0);
    }
    std::size_t planeSize() const { return static_cast<std::size_t>(rows) * paddedWidth; }
    std::size_t sampleStride() const { return planeSize() * kChannels; }
    std::size_t channelStride() const { return planeSize(); }
    std::size_t weightStride() const { return planeSize(); }
    std::size_t offset(int row, int x) const {
        return static_cast<std::size_t>(row) * paddedWidth + x;
    }
    float value(int image, int channel, int row, int x) const {
        return values[image * sampleStride() + channel * channelStride() + offset(row, x)];
    }
    float weight(int image, int row, int x) const {
        return weights[image * weightStride() + offset(row, x)];
    }
};

}  // namespace vpe
