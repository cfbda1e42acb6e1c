// SPDX-License-Identifier: MIT
// PGM / PPM writing through a temporary file and rename(2).
#include "vpe/proto/pnm_image.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "vpe/proto/atomic_file.h"

namespace vpe::proto {

namespace {

void checkShape(const std::filesystem::path& path, int width, int height, int channels,
                int maxValue, std::size_t samples) {
    if (width < 1 || height < 1 || (channels != 1 && channels != 3)) {
        throw std::invalid_argument(path.string() +
                                    ": an image needs a positive size and 1 or 3 "
                                    "channels");
    }
    if (maxValue < 1 || maxValue > 65535) {
        throw std::invalid_argument(path.string() + ": maxval " + std::to_string(maxValue) +
                                    " outside 1..65535");
    }
    const std::size_t expected = static_cast<std::size_t>(width) *
                                 static_cast<std::size_t>(height) *
                                 static_cast<std::size_t>(channels);
    if (samples != expected) {
        throw std::invalid_argument(path.string() + ": " + std::to_string(samples) +
                                    " samples for " + std::to_string(width) + "x" +
                                    std::to_string(height) + "x" + std::to_string(channels));
    }
}

void writeImage(const std::filesystem::path& path, const std::string& header,
                const std::vector<std::uint8_t>& body) {
    writeFileAtomically(
        path, {std::span<const char>(header),
               std::span<const char>(reinterpret_cast<const char*>(body.data()), body.size())});
}

std::string headerOf(int width, int height, int channels, int maxValue) {
    return std::string(channels == 1 ? "P5" : "P6") + "\n" + std::to_string(width) + " " +
           std::to_string(height) + "\n" + std::to_string(maxValue) + "\n";
}

}  // namespace

void writePnmAtomically(const std::filesystem::path& path, int width, int height, int channels,
                        int maxValue, std::span<const std::uint16_t> samples) {
    checkShape(path, width, height, channels, maxValue, samples.size());
    const auto limit = static_cast<std::uint16_t>(maxValue);
    if (std::any_of(samples.begin(), samples.end(), [&](std::uint16_t v) { return v > limit; })) {
        throw std::invalid_argument(path.string() + ": a sample exceeds maxval " +
                                    std::to_string(maxValue));
    }
    std::vector<std::uint8_t> body;
    if (maxValue <= 255) {
        body.assign(samples.begin(), samples.end());
    } else {
        body.resize(2 * samples.size());
        for (std::size_t i = 0; i < samples.size(); ++i) {
            body[2 * i] = static_cast<std::uint8_t>(samples[i] >> 8);  // big-endian (Netpbm)
            body[2 * i + 1] = static_cast<std::uint8_t>(samples[i] & 0xff);
        }
    }
    writeImage(path, headerOf(width, height, channels, maxValue), body);
}

void writePnmAtomically(const std::filesystem::path& path, int width, int height, int channels,
                        std::span<const std::uint8_t> samples) {
    checkShape(path, width, height, channels, 255, samples.size());
    writeImage(path, headerOf(width, height, channels, 255),
               std::vector<std::uint8_t>(samples.begin(), samples.end()));
}

}  // namespace vpe::proto
