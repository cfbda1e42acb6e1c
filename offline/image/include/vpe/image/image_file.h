// SPDX-License-Identifier: MIT
// Whole-image reads and writes through OpenImageIO: masks, normal and position maps, and the
// pictures vpe writes for people (PNG, written atomically).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vpe::image {

struct FloatImage {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> pixels;   // interleaved, row 0 at the top
    bool integerSource = false;  // decoded from an integer format (values scaled to [0, 1])
    float at(int x, int y, int c) const {
        return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c];
    }
};

// What an image file's header says, nothing decoded: size, channels and bits per sample.
struct ImageInfo {
    int width = 0;
    int height = 0;
    int channels = 0;
    int bits = 0;           // per sample: 8, 16, 32, …
    bool floating = false;  // float samples (half, float) rather than integers
};

// Throws InputError naming the file when it is no image OpenImageIO can open.
ImageInfo readImageInfo(const std::filesystem::path& path);

// Reads every channel as float: integer formats are scaled to [0, 1], no transfer function
// is applied. Throws InputError naming the file.
FloatImage readImage(const std::filesystem::path& path);

// The named channels only, in the order asked for (EXR files store channels sorted by name).
// Throws InputError naming the file and the first channel it lacks.
FloatImage readImageChannels(const std::filesystem::path& path,
                             const std::vector<std::string>& channels);

enum class PixelFormat { kUint8, kUint16, kFloat };

// Writes float pixels atomically as 8-bit, 16-bit (values clamped to [0, 1] and scaled)
// or float; the file format follows the extension (.png, .tif, .exr, ...).
// Channel names default to R, G, B(, A).
void writeImage(const std::filesystem::path& path, int width, int height, int channels,
                const std::vector<float>& pixels, PixelFormat format,
                const std::vector<std::string>& channelNames = {});

// Writes an 8-bit image (1, 3 or 4 channels) atomically; the format follows the extension.
void writeImage8(const std::filesystem::path& path, int width, int height, int channels,
                 const std::vector<std::uint8_t>& pixels);

}  // namespace vpe::image
