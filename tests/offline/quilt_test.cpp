// SPDX-License-Identifier: MIT
// Region-restricted Image Quilting: correctness of the FFT search against the exhaustive
// one, region confinement, determinism, and the command's inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "common/input_error.h"
#include "quilt/image_quilter.h"
#include "synth/procedural_noise.h"

namespace vpe::quilt {
namespace {

SourceTexture texturedSource(int size, int channels, std::uint64_t seed) {
    SourceTexture source;
    source.width = source.height = size;
    source.channels = channels;
    source.values.resize(static_cast<std::size_t>(size) * size * channels);
    synth::GradientNoise noise(seed);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            for (int c = 0; c < channels; ++c) {
                source.values[(static_cast<std::size_t>(y) * size + x) * channels + c] =
                    static_cast<float>(noise.fractal(x / 5.0 + 13 * c, y / 5.0, 3));
            }
        }
    }
    return source;
}

std::vector<std::uint8_t> halves(int size) {  // left half region 0, right half region 1
    std::vector<std::uint8_t> labels(static_cast<std::size_t>(size) * size);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            labels[static_cast<std::size_t>(y) * size + x] = x < size / 2 ? 0 : 1;
        }
    }
    return labels;
}

TEST(ImageQuilter, FftSearchWithAllComponentsPicksWhatExhaustiveSearchPicks) {
    const SourceTexture source = texturedSource(48, 6, 3);
    const std::vector<std::uint8_t> labels(48 * 48, 0);
    QuiltSettings settings;
    settings.block = 16;
    settings.overlap = 4;
    settings.tolerance = 0.0;  // the unique best
    settings.pcaVariance = 1.0;
    settings.maxComponents = 6;  // every component: the search is exact up to rounding
    settings.shortlist = 4;
    const RegionQuilt fft = quiltRegion(source, labels, 0, 80, 80, settings);
    settings.search = QuiltSettings::Search::kExhaustive;
    const RegionQuilt exhaustive = quiltRegion(source, labels, 0, 80, 80, settings);
    EXPECT_EQ(fft.components, 6);
    EXPECT_EQ(fft.sourceX, exhaustive.sourceX);
    EXPECT_EQ(fft.sourceY, exhaustive.sourceY);
}

TEST(ImageQuilter, EveryOutputPixelComesFromItsRegion) {
    const SourceTexture source = texturedSource(64, 5, 4);
    const std::vector<std::uint8_t> labels = halves(64);
    QuiltSettings settings;
    settings.block = 16;
    settings.overlap = 4;
    for (int region : {0, 1}) {
        const RegionQuilt quilt = quiltRegion(source, labels, region, 100, 70, settings);
        ASSERT_EQ(quilt.sourceX.size(), 100u * 70u);
        for (std::size_t i = 0; i < quilt.sourceX.size(); ++i) {
            ASSERT_GE(quilt.sourceX[i], 0);
            ASSERT_EQ(labels[static_cast<std::size_t>(quilt.sourceY[i]) * 64 + quilt.sourceX[i]], region)
                << "pixel " << i;
        }
    }
}

TEST(ImageQuilter, IsDeterministicForASeedWhateverTheThreads) {
    const SourceTexture source = texturedSource(64, 4, 5);
    const std::vector<std::uint8_t> labels(64 * 64, 0);
    QuiltSettings settings;
    settings.block = 16;
    settings.overlap = 4;
    settings.threads = 1;
    const RegionQuilt one = quiltRegion(source, labels, 0, 150, 150, settings);
    settings.threads = 3;
    const RegionQuilt three = quiltRegion(source, labels, 0, 150, 150, settings);
    EXPECT_EQ(one.sourceX, three.sourceX);
    EXPECT_EQ(one.sourceY, three.sourceY);
    settings.seed = 2;
    const RegionQuilt other = quiltRegion(source, labels, 0, 150, 150, settings);
    EXPECT_NE(one.sourceX, other.sourceX);
}

TEST(ImageQuilter, CopiesWholeBlocksAndUsesManyOfThem) {
    const SourceTexture source = texturedSource(64, 4, 6);
    const std::vector<std::uint8_t> labels(64 * 64, 0);
    QuiltSettings settings;
    settings.block = 16;
    settings.overlap = 4;
    settings.tolerance = 0.3;
    const RegionQuilt quilt = quiltRegion(source, labels, 0, 128, 128, settings);
    // Inside a block, away from the cuts, neighbouring output pixels copy neighbouring source
    // pixels; across the texture many distinct source offsets are used.
    std::size_t coherent = 0, pairs = 0;
    std::set<std::pair<int, int>> offsets;
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x + 1 < 128; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * 128 + x;
            coherent += quilt.sourceX[i + 1] == quilt.sourceX[i] + 1 && quilt.sourceY[i + 1] == quilt.sourceY[i];
            ++pairs;
            offsets.insert({quilt.sourceX[i] - x, quilt.sourceY[i] - y});
        }
    }
    EXPECT_GT(static_cast<double>(coherent) / pairs, 0.8);
    EXPECT_GT(offsets.size(), 40u);
}

TEST(ImageQuilter, ShrinksTheBlockForAThinRegionAndRefusesATooThinOne) {
    const SourceTexture source = texturedSource(64, 3, 7);
    std::vector<std::uint8_t> labels(64 * 64, 0);
    for (int y = 0; y < 64; ++y) {
        for (int x = 20; x < 32; ++x) {
            labels[static_cast<std::size_t>(y) * 64 + x] = 1;  // a 12-pixel-wide band
        }
        labels[static_cast<std::size_t>(y) * 64 + 40] = 2;  // a 1-pixel line
    }
    QuiltSettings settings;
    settings.block = 32;
    settings.overlap = 6;
    const RegionQuilt band = quiltRegion(source, labels, 1, 40, 40, settings);
    EXPECT_LE(band.block, 12);
    EXPECT_GE(band.block, 8);
    EXPECT_THROW(quiltRegion(source, labels, 2, 40, 40, settings), InputError);
}

}  // namespace
}  // namespace vpe::quilt
