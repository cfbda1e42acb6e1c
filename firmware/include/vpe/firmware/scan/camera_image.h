// SPDX-License-Identifier: MIT
// CameraImage: one capture of a scan as the camera recorded it — samples in [0, maxValue] (255
// for 8 bits, 1023 for 10), rows from the top, one channel (the structured-light patterns'
// luminance: what the frame check reads and the scan folder's PGM stores) or three interleaved
// (R, G, B: the radiometric capture's flat fields, its PPM).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vpe::firmware {

struct CameraImage {
    int width = 0, height = 0;
    int channels = 1;  // 1 or 3
    int maxValue = 255;
    std::vector<std::uint16_t> samples;  // width·height·channels

    std::size_t pixelCount() const {
        return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    }
    std::size_t sampleCount() const { return pixelCount() * static_cast<std::size_t>(channels); }
    int bits() const { return maxValue > 255 ? 10 : 8; }
};

}  // namespace vpe::firmware
