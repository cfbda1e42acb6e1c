// SPDX-License-Identifier: MIT
// The camera's preview and the coverage map: box averages and a grey PNG through zlib.
#include "vpe/firmware/scan/install_images.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <zlib.h>

#include "vpe/proto/luminance.h"

namespace vpe::firmware {

namespace {

// Rec. 709 luminance of one pixel (one channel: itself).
float luminanceAt(const CameraImage& image, std::size_t pixel) {
    if (image.channels == 3) {
        const std::uint16_t* rgb = &image.samples[3 * pixel];
        return proto::luminance709f(rgb[0], rgb[1], rgb[2]);
    }
    return image.samples[pixel];
}

// Box-averages `values` (width × height, each in [0, 255]) to at most maxWidth wide.
template <typename ValueAt>
GreyImage boxAverage(int width, int height, int maxWidth, const ValueAt& valueAt) {
    GreyImage out;
    if (width <= 0 || height <= 0) {
        return out;
    }
    const int factor = std::max(1, (width + std::max(1, maxWidth) - 1) / std::max(1, maxWidth));
    out.width = (width + factor - 1) / factor;
    out.height = (height + factor - 1) / factor;
    out.pixels.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height));
    for (int oy = 0; oy < out.height; ++oy) {
        for (int ox = 0; ox < out.width; ++ox) {
            double sum = 0;
            int count = 0;
            for (int y = oy * factor; y < std::min(height, (oy + 1) * factor); ++y) {
                for (int x = ox * factor; x < std::min(width, (ox + 1) * factor); ++x) {
                    sum += static_cast<double>(
                        valueAt(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                static_cast<std::size_t>(x)));
                    ++count;
                }
            }
            const double mean = count > 0 ? sum / count : 0.0;
            out.pixels[static_cast<std::size_t>(oy) * static_cast<std::size_t>(out.width) +
                       static_cast<std::size_t>(ox)] =
                static_cast<std::uint8_t>(std::clamp(std::lround(mean), 0L, 255L));
        }
    }
    return out;
}

void appendBigEndian(std::string& out, std::uint32_t value) {
    out += static_cast<char>(value >> 24);
    out += static_cast<char>(value >> 16);
    out += static_cast<char>(value >> 8);
    out += static_cast<char>(value);
}

void appendChunk(std::string& out, const char* type, const std::string& data) {
    appendBigEndian(out, static_cast<std::uint32_t>(data.size()));
    const std::string typed = std::string(type, 4) + data;
    out += typed;
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(typed.data()),
                            static_cast<uInt>(typed.size()));
    appendBigEndian(out, static_cast<std::uint32_t>(crc));
}

void checkSameSize(const CameraImage& a, const CameraImage& b) {
    if (a.width != b.width || a.height != b.height || a.samples.size() != a.sampleCount() ||
        b.samples.size() != b.sampleCount()) {
        throw std::invalid_argument("coverage map: captures of different sizes");
    }
}

}  // namespace

GreyImage cameraPreview(const CameraImage& image, int maxWidth) {
    if (image.samples.size() != image.sampleCount()) {
        return {};
    }
    const float scale = 255.0f / static_cast<float>(std::max(1, image.maxValue));
    return boxAverage(image.width, image.height, maxWidth,
                      [&](std::size_t p) { return luminanceAt(image, p) * scale; });
}

std::string encodeGreyPng(const GreyImage& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() !=
            static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height)) {
        throw std::invalid_argument("png: an image whose pixels are not its size");
    }
    // Each row after its filter byte (0: none).
    std::string raw;
    raw.reserve(image.pixels.size() + static_cast<std::size_t>(image.height));
    for (int y = 0; y < image.height; ++y) {
        raw += '\0';
        const auto* row = image.pixels.data() +
                          static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width);
        raw.append(reinterpret_cast<const char*>(row), static_cast<std::size_t>(image.width));
    }
    uLongf packedSize = compressBound(static_cast<uLong>(raw.size()));
    std::string packed(packedSize, '\0');
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packedSize,
                  reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                  Z_DEFAULT_COMPRESSION) != Z_OK) {
        throw std::runtime_error("png: zlib could not compress the image");
    }
    packed.resize(packedSize);
    std::string header;
    appendBigEndian(header, static_cast<std::uint32_t>(image.width));
    appendBigEndian(header, static_cast<std::uint32_t>(image.height));
    header +=
        std::string("\x08\x00\x00\x00\x00", 5);  // 8 bits, grey, deflate, no filter, no interlace
    std::string png("\x89PNG\r\n\x1a\n", 8);
    appendChunk(png, "IHDR", header);
    appendChunk(png, "IDAT", packed);
    appendChunk(png, "IEND", "");
    return png;
}

void CoverageMap::setLit(const CameraImage& white, const CameraImage& black) {
    checkSameSize(white, black);
    width_ = white.width;
    height_ = white.height;
    const std::size_t pixels = white.pixelCount();
    const float floor = static_cast<float>(minContrast_ * white.maxValue);
    range_.resize(pixels);
    lit_.assign(pixels, false);
    undecided_.assign(pixels, 0);
    pairs_ = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
        range_[p] = luminanceAt(white, p) - luminanceAt(black, p);
        lit_[p] = range_[p] >= floor && range_[p] > 0.0f;
    }
}

void CoverageMap::addGrayPair(const CameraImage& pattern, const CameraImage& inverse,
                              double noiseSigma) {
    checkSameSize(pattern, inverse);
    if (!known() || pattern.width != width_ || pattern.height != height_) {
        return;
    }
    // The difference of two frames has √2 σ; a bit reads when pattern and inverse differ by
    // more than three of those and by a quarter of the pixel's white − black.
    const auto noiseFloor = static_cast<float>(3.0 * std::sqrt(2.0) * noiseSigma);
    for (std::size_t p = 0; p < lit_.size(); ++p) {
        if (!lit_[p]) {
            continue;
        }
        const float difference = std::abs(luminanceAt(pattern, p) - luminanceAt(inverse, p));
        if (!(difference > noiseFloor && difference > 0.25f * range_[p]) && undecided_[p] < 255) {
            ++undecided_[p];
        }
    }
    ++pairs_;
}

bool CoverageMap::decodable(std::size_t pixel) const {
    // A stripe's edge blurs one Gray bit at a time (neighbouring codes differ in one bit).
    return lit_[pixel] && pairs_ > 0 && undecided_[pixel] <= 1;
}

double CoverageMap::litFraction() const {
    if (lit_.empty()) {
        return 0.0;
    }
    return static_cast<double>(std::count(lit_.begin(), lit_.end(), true)) /
           static_cast<double>(lit_.size());
}

double CoverageMap::decodableFraction() const {
    if (lit_.empty() || pairs_ == 0) {
        return 0.0;
    }
    std::size_t count = 0;
    for (std::size_t p = 0; p < lit_.size(); ++p) {
        count += decodable(p) ? 1 : 0;
    }
    return static_cast<double>(count) / static_cast<double>(lit_.size());
}

GreyImage CoverageMap::image(int maxWidth) const {
    return boxAverage(width_, height_, maxWidth, [this](std::size_t p) -> float {
        if (!lit_[p]) {
            return kDark;
        }
        return pairs_ == 0 ? kLit : (decodable(p) ? kDecodable : kLit);
    });
}

}  // namespace vpe::firmware
