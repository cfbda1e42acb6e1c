// SPDX-License-Identifier: MIT
// ImageBandReader: decoding on many threads gives exactly what one thread gives, and both are
// exactly the reference decoding (the whole image through OpenImageIO, then the transfer
// function value by value), for every pixel format, grey and alpha images, masks, and bands
// of any height over widths that are not a multiple of the chunk.
#include "vpe/capture/image_band_reader.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "vpe/capture/decoded_image_cache.h"
#include "vpe/common/input_error.h"
#include "vpe/proto/srgb.h"

#include "support/test_data.h"

namespace vpe {
namespace {

constexpr int kWidth = 37;  // two full chunks and a partial one
constexpr int kHeight = 13;

struct ImageKind {
    const char* extension;
    OIIO::TypeDesc format;
    int channels;
};

// Pixels over the whole range, full scale included (saturation) and, for float, values that
// are not finite (unusable samples) and negative ones.
void writeImage(const std::filesystem::path& path, const ImageKind& kind, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<float> pixels(static_cast<std::size_t>(kWidth) * kHeight * kind.channels);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        pixels[i] = i % 17 == 0 ? 1.0f : uniform(random);
        if (kind.format == OIIO::TypeDesc::FLOAT) {
            if (i % 29 == 0) {
                pixels[i] = std::numeric_limits<float>::quiet_NaN();
            } else if (i % 31 == 0) {
                pixels[i] = -pixels[i];
            } else if (i % 37 == 0) {
                pixels[i] = std::numeric_limits<float>::infinity();
            }
        }
    }
    OIIO::ImageSpec spec(kWidth, kHeight, kind.channels, kind.format);
    if (std::string(kind.extension) == ".jpg") {
        spec.attribute("CompressionQuality", 90);
    }
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), spec) &&
                out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close())
        << path;
}

capture::Capture writeCapture(const std::filesystem::path& dir, const ImageKind& kind, int images) {
    capture::Capture capture;
    capture.source = dir / "capture.json";
    for (int i = 0; i < images; ++i) {
        const std::filesystem::path file = dir / ("image" + std::to_string(i) + kind.extension);
        writeImage(file, kind, static_cast<std::uint32_t>(i + 1));
        capture.images.push_back({file, proto::Vec3d{0, 0, 1}, 1.0, 0});
    }
    return capture;
}

// The band's samples as read in bands of `bandRows` on `threads` threads, row by row, in
// the band-independent order [image][channel][y][x] (values), [image][y][x] (flags).
struct Decoded {
    std::vector<float> values;
    std::vector<float> weights;
    std::vector<std::uint8_t> saturated;
};

Decoded readAll(const capture::Capture& capture, unsigned threads, int bandRows,
                const std::vector<std::uint8_t>& mask) {
    capture::ImageBandReader reader(capture, threads);
    const int n = reader.imageCount();
    Decoded out;
    out.values.resize(static_cast<std::size_t>(n) * 3 * kWidth * kHeight);
    out.weights.resize(static_cast<std::size_t>(n) * kWidth * kHeight);
    out.saturated.resize(out.weights.size());
    capture::SampleBand band;
    for (int y0 = 0; y0 < kHeight; y0 += bandRows) {
        const int rows = std::min(bandRows, kHeight - y0);
        reader.readBand(y0, rows, mask.empty() ? nullptr : mask.data(), band);
        for (int i = 0; i < n; ++i) {
            for (int r = 0; r < rows; ++r) {
                for (int x = 0; x < kWidth; ++x) {
                    const std::size_t at =
                        (static_cast<std::size_t>(i) * kHeight + y0 + r) * kWidth + x;
                    for (int c = 0; c < 3; ++c) {
                        out.values[(static_cast<std::size_t>(i) * 3 + c) * kHeight * kWidth +
                                   static_cast<std::size_t>(y0 + r) * kWidth + x] =
                            band.value(i, c, r, x);
                    }
                    out.weights[at] = band.weight(i, r, x);
                    out.saturated[at] = band.isSaturated(i, r, x) ? 1 : 0;
                }
            }
        }
        // Lanes past the row's end stay empty.
        for (int r = 0; r < rows; ++r) {
            for (int x = kWidth; x < band.chunksPerRow * capture::SampleBand::kChunkWidth; ++x) {
                EXPECT_EQ(band.weights[band.sampleIndex(0, r, x)], 0.0f);
                EXPECT_EQ(band.values[band.valueIndex(0, 2, r, x)], 0.0f);
            }
        }
    }
    return out;
}

// What the decoder must produce, value by value, from the whole image.
Decoded reference(const capture::Capture& capture, const std::vector<std::uint8_t>& mask,
                  bool srgb) {
    const auto n = capture.images.size();
    Decoded out;
    out.values.resize(n * 3 * kWidth * kHeight);
    out.weights.resize(n * kWidth * kHeight);
    out.saturated.resize(out.weights.size());
    for (std::size_t i = 0; i < n; ++i) {
        auto input = OIIO::ImageInput::open(capture.images[i].file.string());
        const OIIO::ImageSpec spec = input->spec();
        const bool integer = spec.format != OIIO::TypeDesc::FLOAT;
        const double full = spec.format == OIIO::TypeDesc::UINT8 ? 255.0 : 65535.0;
        std::vector<float> pixels(static_cast<std::size_t>(kWidth) * kHeight * spec.nchannels);
        std::vector<std::uint32_t> codes(pixels.size());
        if (integer) {
            input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT32, codes.data());
        } else {
            input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
        }
        const int colour = spec.nchannels >= 3 ? 1 : 0;
        for (int y = 0; y < kHeight; ++y) {
            for (int x = 0; x < kWidth; ++x) {
                const std::size_t pixel = static_cast<std::size_t>(y) * kWidth + x;
                bool usable = mask.empty() || mask[pixel] != 0;
                bool saturated = false;
                for (int c = 0; c < 3; ++c) {
                    const std::size_t in = pixel * spec.nchannels + c * colour;
                    float value;
                    if (integer) {
                        // OpenImageIO widens 8 and 16-bit codes to 32 bits by replication.
                        const std::uint32_t code = spec.format == OIIO::TypeDesc::UINT8
                                                       ? codes[in] >> 24
                                                       : codes[in] >> 16;
                        saturated |= code == static_cast<std::uint32_t>(full);
                        value = srgb ? static_cast<float>(proto::srgbToLinear(code / full))
                                     : static_cast<float>(code) / static_cast<float>(full);
                    } else {
                        value = pixels[in];
                        if (!std::isfinite(value)) {
                            usable = false;
                            value = 0.0f;
                        } else if (srgb) {
                            value = static_cast<float>(
                                std::copysign(proto::srgbToLinear(std::fabs(value)), value));
                        }
                    }
                    out.values[(i * 3 + c) * kHeight * kWidth + pixel] = value;
                }
                out.weights[i * kHeight * kWidth + pixel] = usable ? 1.0f : 0.0f;
                out.saturated[i * kHeight * kWidth + pixel] = saturated ? 1 : 0;
            }
        }
    }
    return out;
}

template <typename A, typename B>
bool sameBits(const A& a, const B& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expectSame(const Decoded& a, const Decoded& b, const std::string& what) {
    EXPECT_TRUE(sameBits(a.values, b.values)) << what << ": values differ";
    EXPECT_TRUE(sameBits(a.weights, b.weights)) << what << ": weights differ";
    EXPECT_EQ(a.saturated, b.saturated) << what << ": saturation flags differ";
}

struct Case {
    const char* name;
    ImageKind kind;
    capture::ImageEncoding encoding;
    bool srgb;  // what the encoding resolves to for this kind
};

const Case kCases[] = {
    {"jpeg_srgb8", {".jpg", OIIO::TypeDesc::UINT8, 3}, capture::ImageEncoding::kAuto, true},
    {"png8_grey", {".png", OIIO::TypeDesc::UINT8, 1}, capture::ImageEncoding::kAuto, true},
    {"png8_linear_rgba",
     {".png", OIIO::TypeDesc::UINT8, 4},
     capture::ImageEncoding::kLinear,
     false},
    {"png16_linear_rgb", {".png", OIIO::TypeDesc::UINT16, 3}, capture::ImageEncoding::kAuto, false},
    {"png16_srgb_grey_alpha",
     {".png", OIIO::TypeDesc::UINT16, 2},
     capture::ImageEncoding::kSrgb,
     true},
    {"exr_float", {".exr", OIIO::TypeDesc::FLOAT, 3}, capture::ImageEncoding::kAuto, false},
    {"exr_float_srgb", {".exr", OIIO::TypeDesc::FLOAT, 4}, capture::ImageEncoding::kSrgb, true},
};

void PrintTo(const Case& c, std::ostream* out) {
    *out << c.name;
}

class ImageBandReaderFormats : public ::testing::TestWithParam<Case> {};

TEST_P(ImageBandReaderFormats, ParallelDecodingEqualsSerialAndTheReference) {
    const Case& c = GetParam();
    testing::TemporaryFolder folder;
    capture::Capture capture = writeCapture(folder.path(), c.kind, 9);
    capture.encoding = c.encoding;
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(kWidth) * kHeight);
    for (std::size_t p = 0; p < mask.size(); ++p) {
        mask[p] = p % 7 == 3 ? 0 : 1;
    }
    for (const std::vector<std::uint8_t>& m : {std::vector<std::uint8_t>{}, mask}) {
        const std::string what = std::string(c.name) + (m.empty() ? "" : ", masked");
        const Decoded expected = reference(capture, m, c.srgb);
        const Decoded serial = readAll(capture, 1, kHeight, m);
        expectSame(serial, expected, what + ", one thread, one band");
        for (unsigned threads : {2u, 4u, 7u}) {
            for (int bandRows : {1, 4, 5}) {
                expectSame(readAll(capture, threads, bandRows, m), serial,
                           what + ", " + std::to_string(threads) + " threads, bands of " +
                               std::to_string(bandRows));
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(All, ImageBandReaderFormats, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& param) {
                             return std::string(param.param.name);
                         });

TEST(ImageBandReader, ABandReusedForTheSameShapeHoldsOnlyNewSamples) {
    testing::TemporaryFolder folder;
    const capture::Capture capture =
        writeCapture(folder.path(), {".png", OIIO::TypeDesc::UINT8, 3}, 3);
    capture::ImageBandReader reader(capture, 2);
    capture::SampleBand first, reused;
    reader.readBand(0, 6, nullptr, reused);
    // Rows 6..11 into the band that held rows 0..5, and into a fresh one.
    capture::ImageBandReader again(capture, 2);
    again.readBand(0, 6, nullptr, first);
    reader.readBand(6, 6, nullptr, reused);
    capture::SampleBand fresh;
    again.readBand(6, 6, nullptr, fresh);
    EXPECT_TRUE(sameBits(reused.values, fresh.values));
    EXPECT_TRUE(sameBits(reused.weights, fresh.weights));
    EXPECT_EQ(reused.saturated, fresh.saturated);
    EXPECT_EQ(reused.fullyUsable, fresh.fullyUsable);
}

// A capture read whole once is read again from the process's decoded images, exactly; an
// image rewritten since is decoded anew.
TEST(ImageBandReader, ACaptureReadAgainComesFromItsDecodedImagesUntilAFileChanges) {
    testing::TemporaryFolder folder;
    const ImageKind kind{".png", OIIO::TypeDesc::UINT8, 3};
    const capture::Capture capture = writeCapture(folder.path(), kind, 3);
    const capture::DecodedImageCache& cache = capture::DecodedImageCache::instance();
    EXPECT_EQ(cache.find(capture.images[1].file), nullptr);
    // Made before the images are decoded, it takes them from the cache once it reads.
    capture::ImageBandReader early(capture, 2);
    const Decoded first = readAll(capture, 2, 5, {});
    for (const capture::CaptureImage& image : capture.images) {
        EXPECT_NE(cache.find(image.file), nullptr) << image.file;
    }
    expectSame(readAll(capture, 2, 4, {}), first, "read again");
    capture::SampleBand whole, again;
    early.readBand(0, kHeight, nullptr, whole);
    capture::ImageBandReader(capture, 1).readBand(0, kHeight, nullptr, again);
    EXPECT_TRUE(sameBits(whole.values, again.values));
    EXPECT_TRUE(sameBits(whole.weights, again.weights));
    expectSame(first, reference(capture, {}, true), "first read");

    // Another image under the same name: a later modification time.
    writeImage(capture.images[1].file, kind, 77);
    EXPECT_EQ(cache.find(capture.images[1].file), nullptr);
    const Decoded rewritten = readAll(capture, 2, 5, {});
    expectSame(rewritten, reference(capture, {}, true), "after the rewrite");
    EXPECT_FALSE(sameBits(rewritten.values, first.values));
}

// The cache keeps what its budget holds, dropping what it held before to make room.
TEST(DecodedImageCache, KeepsWhatItsBudgetHolds) {
    testing::TemporaryFolder folder;
    const capture::Capture capture =
        writeCapture(folder.path(), {".png", OIIO::TypeDesc::UINT8, 3}, 2);
    capture::DecodedImageCache cache(100);
    const auto image = [](std::size_t bytes) {
        auto made = std::make_shared<capture::DecodedImageCache::Image>();
        made->bytes.resize(bytes);
        return made;
    };
    EXPECT_TRUE(cache.admits(100));
    EXPECT_FALSE(cache.admits(101));
    cache.insert(capture.images[0].file, image(60));
    EXPECT_NE(cache.find(capture.images[0].file), nullptr);
    cache.insert(capture.images[1].file, image(60));
    EXPECT_EQ(cache.find(capture.images[0].file), nullptr);
    EXPECT_NE(cache.find(capture.images[1].file), nullptr);
    cache.insert(capture.images[0].file, image(101));  // never held
    EXPECT_EQ(cache.find(capture.images[0].file), nullptr);
    EXPECT_EQ(cache.find(folder.path() / "absent.png"), nullptr);
}

TEST(ImageBandReader, ACorruptImageIsNamedInOneLine) {
    testing::TemporaryFolder folder;
    capture::Capture capture = writeCapture(folder.path(), {".png", OIIO::TypeDesc::UINT8, 3}, 4);
    {
        std::ofstream broken(capture.images[2].file, std::ios::binary | std::ios::trunc);
        broken << "not a png";
    }
    try {
        capture::ImageBandReader reader(capture, 4);
        FAIL() << "a corrupt image was accepted";
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("image2.png"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

// A calibrated response (ImageEncoding::kGamma) decodes the same codes as a power law: each
// sample is (code / full scale)^γ, for 8- and 16-bit images alike.
TEST(ImageBandReader, ACalibratedResponseDecodesCodesAsAPowerLaw) {
    for (const OIIO::TypeDesc format : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16}) {
        testing::TemporaryFolder folder;
        capture::Capture capture = writeCapture(folder.path(), {".png", format, 3}, 2);
        capture.encoding = capture::ImageEncoding::kLinear;
        capture::SampleBand codes;
        capture::ImageBandReader(capture, 1).readBand(0, kHeight, nullptr, codes);
        capture.encoding = capture::ImageEncoding::kGamma;
        capture.gamma = 1.4;
        capture::SampleBand decoded;
        capture::ImageBandReader(capture, 2).readBand(0, kHeight, nullptr, decoded);
        ASSERT_EQ(codes.values.size(), decoded.values.size());
        for (std::size_t i = 0; i < codes.values.size(); ++i) {
            ASSERT_NEAR(decoded.values[i], std::pow(static_cast<double>(codes.values[i]), 1.4),
                        1e-6)
                << "sample " << i;
        }
        EXPECT_EQ(codes.weights, decoded.weights);
    }
}

TEST(ImageBandReader, ACalibratedResponseRefusesFloatImagesByName) {
    testing::TemporaryFolder folder;
    capture::Capture capture = writeCapture(folder.path(), {".exr", OIIO::TypeDesc::FLOAT, 3}, 1);
    capture.encoding = capture::ImageEncoding::kGamma;
    capture.gamma = 1.4;
    try {
        capture::ImageBandReader reader(capture, 1);
        FAIL() << "a float image under a calibrated response was accepted";
    } catch (const common::InputError& error) {
        EXPECT_NE(std::string(error.what()).find(".exr"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("integer images only"), std::string::npos);
    }
}

}  // namespace
}  // namespace vpe
