// SPDX-License-Identifier: MIT
// Quilting quality metrics on hand-built position maps: a verbatim copy, a pixel shuffle, two
// blocks, a copy from the wrong region; the sliced Wasserstein distance; the positions files;
// `vpe quilt-quality` end to end.
#include "vpe/quilt/quilt_quality.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/quilt/quilt_folder.h"

#include "support/command_runner.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using quilt::PositionMap;
using quilt::RegionQuality;

constexpr int kHarmonics = 1;
constexpr int kDims = 3 * proto::coefficientCount(kHarmonics);
constexpr int kSourceWidth = 56, kSourceHeight = 48;
constexpr int kRegionSplit = 36;  // region 0: x < 36, region 1: the rest
constexpr int kOutput = 32;

// A smooth texture: per dimension two plane waves of 9–14 pixel periods, plus a little
// noise, so neighbours are much closer than random pairs and the spectrum has a shape.
model::CoefficientImage smoothSource() {
    model::CoefficientImage image;
    image.width = kSourceWidth;
    image.height = kSourceHeight;
    image.dims = kDims;
    image.harmonics = kHarmonics;
    image.values.resize(static_cast<std::size_t>(kSourceWidth) * kSourceHeight * kDims);
    image.valid.assign(static_cast<std::size_t>(kSourceWidth) * kSourceHeight, 1);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0, 1);
    for (int d = 0; d < kDims; ++d) {
        double wave[2][4];
        for (auto& w : wave) {
            const double angle = uniform(random) * 2 * M_PI;
            const double period = 9 + 5 * uniform(random);
            w[0] = std::cos(angle) * 2 * M_PI / period;
            w[1] = std::sin(angle) * 2 * M_PI / period;
            w[2] = uniform(random) * 2 * M_PI;
            w[3] = 0.5 + uniform(random);
        }
        for (int y = 0; y < kSourceHeight; ++y) {
            for (int x = 0; x < kSourceWidth; ++x) {
                double v = 0.02 * (uniform(random) - 0.5);
                for (const auto& w : wave) {
                    v += w[3] * std::sin(w[0] * x + w[1] * y + w[2]);
                }
                image.values[(static_cast<std::size_t>(y) * kSourceWidth + x) * kDims + d] =
                    static_cast<float>(v);
            }
        }
    }
    return image;
}

std::vector<std::uint8_t> splitLabels() {
    std::vector<std::uint8_t> labels(static_cast<std::size_t>(kSourceWidth) * kSourceHeight);
    for (int y = 0; y < kSourceHeight; ++y) {
        for (int x = 0; x < kSourceWidth; ++x) {
            labels[static_cast<std::size_t>(y) * kSourceWidth + x] = x < kRegionSplit ? 0 : 1;
        }
    }
    return labels;
}

// The output a copying quilter makes from these positions.
model::CoefficientImage copyOf(const model::CoefficientImage& source,
                               const PositionMap& positions) {
    model::CoefficientImage out;
    out.width = positions.width;
    out.height = positions.height;
    out.dims = source.dims;
    out.harmonics = source.harmonics;
    out.values.resize(positions.sourceX.size() * source.dims);
    out.valid.assign(positions.sourceX.size(), 1);
    for (std::size_t p = 0; p < positions.sourceX.size(); ++p) {
        const std::size_t s =
            static_cast<std::size_t>(positions.sourceY[p]) * source.width + positions.sourceX[p];
        std::copy_n(source.at(s), source.dims, out.values.data() + p * source.dims);
    }
    return out;
}

PositionMap offsetCopy(int dx, int dy, int size = kOutput) {
    PositionMap map;
    map.resize(size, size);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            map.sourceX[map.pixel(x, y)] = x + dx;
            map.sourceY[map.pixel(x, y)] = y + dy;
        }
    }
    return map;
}

// Every output pixel from a randomly chosen pixel of the region.
PositionMap shuffle(int region, std::uint32_t seed) {
    const std::vector<std::uint8_t> labels = splitLabels();
    std::vector<std::size_t> pixels;
    for (std::size_t p = 0; p < labels.size(); ++p) {
        if (labels[p] == region) {
            pixels.push_back(p);
        }
    }
    std::mt19937 random(seed);
    std::shuffle(pixels.begin(), pixels.end(), random);
    PositionMap map;
    map.resize(kOutput, kOutput);
    // Region 1 has fewer pixels than the output: some are used twice, far apart.
    for (std::size_t p = 0; p < map.sourceX.size(); ++p) {
        const std::size_t s = pixels[p % pixels.size()];
        map.sourceX[p] = static_cast<std::int32_t>(s % kSourceWidth);
        map.sourceY[p] = static_cast<std::int32_t>(s / kSourceWidth);
    }
    return map;
}

RegionQuality measure(const PositionMap& positions, int region = 0) {
    static const model::CoefficientImage source = smoothSource();
    return quilt::measureRegionQuality(source, splitLabels(), region, copyOf(source, positions),
                                       positions, quilt::QualityOptions{});
}

TEST(QuiltQuality, VerbatimCopyIsOneComponentWithoutSeams) {
    const RegionQuality q = measure(offsetCopy(2, 8));
    EXPECT_EQ(q.outputPixels, 1024u);
    EXPECT_EQ(q.positionedPixels, 1024u);
    EXPECT_EQ(q.sourcePixels, 36u * 48u);
    EXPECT_EQ(q.correctness, 1.0);
    EXPECT_EQ(q.copyMaxDifference, 0.0);
    EXPECT_EQ(q.largestCopy, 1024u);
    EXPECT_EQ(q.largestCopyFraction, 1.0);
    EXPECT_EQ(q.largestCopyOffsetX, 2);
    EXPECT_EQ(q.largestCopyOffsetY, 8);
    EXPECT_EQ(q.seamPairs, 0u);
    EXPECT_EQ(q.interiorPairs, 2u * 32u * 31u);
    EXPECT_FALSE(q.interiorFromSource);
    EXPECT_TRUE(std::isnan(q.seamRatio));  // no seams: undefined, not 0 or 1
    EXPECT_GT(q.interiorMsd, 0);
    EXPECT_GT(q.wasserstein, 0);  // a part of the region, not all of it
    EXPECT_TRUE(std::isfinite(q.wassersteinRatio));
    EXPECT_EQ(q.spectrumWindowWidth, 32);
    EXPECT_EQ(q.spectrumWindowHeight, 18);
    EXPECT_EQ(q.spectrumComponents, 4);
    EXPECT_EQ(q.spectrumTiles, 1);
    EXPECT_TRUE(std::isfinite(q.spectrum));
    EXPECT_GT(q.spectrumSelf, 0);
}

TEST(QuiltQuality, PixelShuffleHasTinyComponentsAndHugeSeams) {
    const RegionQuality verbatim = measure(offsetCopy(2, 8));
    const RegionQuality q = measure(shuffle(0, 3));
    EXPECT_EQ(q.correctness, 1.0);
    EXPECT_EQ(q.copyMaxDifference, 0.0);
    EXPECT_LE(q.largestCopy, 3u);
    EXPECT_LT(q.largestCopyFraction, 0.01);
    EXPECT_GT(q.seamPairs, 1900u);
    EXPECT_GT(q.seamRatio, 5.0);
    // White noise instead of the region's waves: far from the source spectrum.
    EXPECT_GT(q.spectrum, 3 * verbatim.spectrum);
    EXPECT_GT(q.spectrumRatio, 2.0);
}

TEST(QuiltQuality, TwoBlocksHaveOneSeamColumn) {
    PositionMap positions = offsetCopy(2, 8);
    for (int y = 0; y < kOutput; ++y) {
        for (int x = 16; x < kOutput; ++x) {
            positions.sourceX[positions.pixel(x, y)] = x - 16;  // the right half from x = 0
            positions.sourceY[positions.pixel(x, y)] = y + 3;
        }
    }
    const RegionQuality q = measure(positions);
    EXPECT_EQ(q.correctness, 1.0);
    EXPECT_EQ(q.largestCopy, 512u);
    EXPECT_EQ(q.largestCopyFraction, 0.5);
    EXPECT_EQ(q.seamPairs, 32u);  // the pairs across the column boundary 15 | 16
    EXPECT_EQ(q.interiorPairs, 2u * 32u * 31u - 32u);
    EXPECT_GT(q.seamRatio, 1.5);  // unrelated sources meet there
}

TEST(QuiltQuality, CopiesFromTheWrongRegionLowerCorrectness) {
    PositionMap positions = offsetCopy(2, 8);
    positions.sourceX[positions.pixel(5, 5)] = 40;  // region 1
    positions.sourceY[positions.pixel(5, 5)] = 10;
    const RegionQuality q = measure(positions);
    EXPECT_EQ(q.correctPixels, 1023u);
    EXPECT_EQ(q.correctness, 1023.0 / 1024.0);
    EXPECT_LT(q.correctness, 1.0);
    EXPECT_EQ(q.largestCopy, 1023u);
    // The same positions judged as region 1: everything else is wrong.
    EXPECT_EQ(measure(positions, 1).correctPixels, 1u);
}

TEST(QuiltQuality, CoefficientsThatAreNotCopiesAreReported) {
    const model::CoefficientImage source = smoothSource();
    const PositionMap positions = offsetCopy(2, 8);
    model::CoefficientImage output = copyOf(source, positions);
    output.values[7 * kDims + 3] += 0.25f;
    const RegionQuality q = quilt::measureRegionQuality(source, splitLabels(), 0, output, positions,
                                                        quilt::QualityOptions{});
    EXPECT_NEAR(q.copyMaxDifference, 0.25, 1e-6);
}

// ---- sliced Wasserstein ---------------------------------------------------------------

std::vector<float> randomSet(std::size_t count, int dims, std::uint32_t seed) {
    std::mt19937 random(seed);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::vector<float> set(count * dims);
    for (float& v : set) {
        v = normal(random);
    }
    return set;
}

TEST(QuiltQualitySlicedWasserstein, IsZeroForIdenticalDistributions) {
    const int dims = 12;
    const std::vector<float> a = randomSet(500, dims, 1);
    // The same vectors in another order.
    std::vector<std::size_t> order(500);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::shuffle(order.begin(), order.end(), std::mt19937(5));
    std::vector<float> permuted;
    for (std::size_t i : order) {
        permuted.insert(permuted.end(), a.begin() + static_cast<long>(i * dims),
                        a.begin() + static_cast<long>((i + 1) * dims));
    }
    const quilt::SlicedWassersteinOptions options;
    EXPECT_EQ(quilt::slicedWasserstein(a.data(), 500, permuted.data(), 500, dims, options), 0.0);
    // Every vector twice: the same distribution from a set of another size.
    std::vector<float> doubled = a;
    doubled.insert(doubled.end(), a.begin(), a.end());
    EXPECT_EQ(quilt::slicedWasserstein(a.data(), 500, doubled.data(), 1000, dims, options), 0.0);
}

TEST(QuiltQualitySlicedWasserstein, MeasuresAShift) {
    const int dims = 12;
    const std::vector<float> a = randomSet(400, dims, 2);
    std::vector<float> shifted = a;
    for (float& v : shifted) {
        v += 0.1f;
    }
    quilt::SlicedWassersteinOptions options;
    const double distance =
        quilt::slicedWasserstein(a.data(), 400, shifted.data(), 400, dims, options);
    // Along a unit direction θ the shift is θ·(0.1, ..., 0.1), whose mean square over random
    // directions is 0.1².
    EXPECT_GT(distance, 0.06);
    EXPECT_LT(distance, 0.14);
    // Another sample of the same distribution is closer than the shifted copy is.
    const std::vector<float> b = randomSet(400, dims, 3);
    const double sampling = quilt::slicedWasserstein(a.data(), 400, b.data(), 400, dims, options);
    EXPECT_GT(sampling, 0);
    // Deterministic, whatever the thread count.
    options.threads = 4;
    EXPECT_EQ(quilt::slicedWasserstein(a.data(), 400, shifted.data(), 400, dims, options),
              distance);
    options.seed = 2;
    EXPECT_NE(quilt::slicedWasserstein(a.data(), 400, shifted.data(), 400, dims, options),
              distance);
}

// ---- files ----------------------------------------------------------------------------

void writeModel(const std::filesystem::path& path, const model::CoefficientImage& image) {
    model::ModelInfo info;
    info.width = image.width;
    info.height = image.height;
    info.harmonics = image.harmonics;
    model::ModelRows rows;
    rows.resize(image.width, image.height, proto::coefficientCount(image.harmonics));
    rows.coefficient = image.values;  // the same [pixel][channel][k] layout
    for (std::size_t p = 0; p < image.valid.size(); ++p) {
        rows.valid[p] = image.valid[p];
        rows.normal[p * 3 + 2] = 1.0f;
    }
    model::ModelWriter writer(path, info);
    writer.writeRows(0, rows);
    writer.finish();
}

TEST(QuiltQualityPositions, PositionsRoundTripAndBadValuesAreNamed) {
    const testing::TemporaryFolder folder;
    const PositionMap copy = offsetCopy(2, 8);
    quilt::writePositionMap(quilt::positionsPath(folder.path(), 1), copy, 1);
    const auto maps =
        quilt::readPositionMaps(folder.path(), 2, kOutput, kOutput, kSourceWidth, kSourceHeight);
    ASSERT_EQ(maps.size(), 2u);
    EXPECT_EQ(maps[1].sourceX, copy.sourceX);
    EXPECT_EQ(maps[1].sourceY, copy.sourceY);
    EXPECT_FALSE(maps[0].known(0));  // no positions0.exr

    auto expectError = [&](const std::vector<float>& pixels,
                           const std::vector<std::string>& mentions) {
        const testing::TemporaryFolder bad;
        image::writeImage(quilt::positionsPath(bad.path(), 0), 2, 1, 3, pixels,
                          image::PixelFormat::kFloat, {"source.x", "source.y", "region"});
        try {
            quilt::readPositionMaps(bad.path(), 2, 2, 1, 10, 10);
            ADD_FAILURE() << "no InputError";
        } catch (const common::InputError& error) {
            for (const std::string& mention : mentions) {
                EXPECT_NE(std::string(error.what()).find(mention), std::string::npos)
                    << mention << " not in " << error.what();
            }
        }
    };
    expectError({0, 0, 0, 10, 3, 0}, {"positions0.exr", "pixel (1, 0)", "outside"});
    expectError({0, 0, 0, 1.5f, 3, 0}, {"pixel (1, 0)", "source.x", "not an integer"});
    expectError({0, 0, 2, 1, 3, 0}, {"pixel (0, 0)", "region 2"});
    // Two files giving one pixel of one region.
    {
        const testing::TemporaryFolder twice;
        quilt::writePositionMap(quilt::positionsPath(twice.path(), 0), offsetCopy(0, 0, 4), 0);
        quilt::writePositionMap(twice.path() / "positions.exr", offsetCopy(1, 1, 4), 0);
        EXPECT_THROW(quilt::readPositionMaps(twice.path(), 1, 4, 4, 10, 10), common::InputError);
    }
    const testing::TemporaryFolder empty;
    EXPECT_THROW(quilt::readPositionMaps(empty.path(), 1, 4, 4, 10, 10), common::InputError);
}

constexpr auto& vpe = testing::vpeCommand;

// A quilt folder as vpe quilt writes it: region 0 a verbatim copy, region 1 a shuffle.
void writeQuiltFolder(const testing::TemporaryFolder& folder) {
    const model::CoefficientImage source = smoothSource();
    writeModel(folder / "model.exr", source);
    image::writeImage8(folder / "labels.png", kSourceWidth, kSourceHeight, 1, splitLabels());
    const PositionMap copy = offsetCopy(2, 8);
    const PositionMap shuffled = shuffle(1, 4);
    writeModel(folder / "quilt" / "region0.exr", copyOf(source, copy));
    writeModel(folder / "quilt" / "region1.exr", copyOf(source, shuffled));
    quilt::writePositionMap(quilt::positionsPath(folder / "quilt", 0), copy, 0);
    quilt::writePositionMap(quilt::positionsPath(folder / "quilt", 1), shuffled, 1);
}

TEST(QuiltQualityCli, ReportsEveryRegion) {
    const testing::TemporaryFolder folder;
    writeQuiltFolder(folder);
    const std::vector<std::string> arguments = {"quilt-quality", (folder / "model.exr").string(),
                                                "--labels",      (folder / "labels.png").string(),
                                                "--quilt",       (folder / "quilt").string()};
    const testing::CommandResult text = testing::runCommand(vpe(arguments));
    ASSERT_EQ(text.exitStatus, 0) << text.err;
    EXPECT_NE(text.out.find("region correctness"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("largest verbatim copy"), std::string::npos) << text.out;

    std::vector<std::string> json = arguments;
    json.push_back("--json");
    const testing::CommandResult result = testing::runCommand(vpe(json));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    std::string out = result.out;
    while (!out.empty() && out.back() == '\n') {
        out.pop_back();
    }
    const nlohmann::json report = nlohmann::json::parse(out.substr(out.rfind('\n') + 1));
    ASSERT_EQ(report["regions"].size(), 2u);
    const nlohmann::json& verbatim = report["regions"][0];
    EXPECT_EQ(verbatim["correctness"], 1.0);
    EXPECT_EQ(verbatim["copy_max_difference"], 0.0);
    EXPECT_EQ(verbatim["largest_copy"]["fraction"], 1.0);
    EXPECT_EQ(verbatim["largest_copy"]["offset"], nlohmann::json({2, 8}));
    EXPECT_EQ(verbatim["seams"]["seam_pairs"], 0);
    EXPECT_TRUE(verbatim["seams"]["ratio"].is_null());
    EXPECT_TRUE(verbatim["sliced_wasserstein"]["ratio"].is_number());
    EXPECT_TRUE(verbatim["spectrum"]["ratio"].is_number());
    const nlohmann::json& shuffled = report["regions"][1];
    EXPECT_EQ(shuffled["region"], 1);
    EXPECT_EQ(shuffled["correctness"], 1.0);
    EXPECT_GT(shuffled["seams"]["ratio"].get<double>(), 3.0);
    EXPECT_LT(shuffled["largest_copy"]["fraction"].get<double>(), 0.01);
}

TEST(QuiltQualityCli, MissingOrMismatchedInputsExitTwo) {
    const testing::TemporaryFolder folder;
    writeQuiltFolder(folder);
    auto run = [&](const std::string& labels) {
        return testing::runCommand(
            vpe({"quilt-quality", (folder / "model.exr").string(), "--labels", labels, "--quilt",
                 (folder / "quilt").string()}));
    };
    // Labels of another size.
    image::writeImage8(folder / "small.png", 4, 4, 1, std::vector<std::uint8_t>(16, 0));
    testing::CommandResult result = run((folder / "small.png").string());
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_NE(result.err.find("small.png"), std::string::npos) << result.err;
    // Labels without region 1.
    image::writeImage8(folder / "one.png", kSourceWidth, kSourceHeight, 1,
                       std::vector<std::uint8_t>(kSourceWidth * kSourceHeight, 0));
    result = run((folder / "one.png").string());
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_NE(result.err.find("region 1"), std::string::npos) << result.err;
    // No positions.
    std::filesystem::remove(quilt::positionsPath(folder / "quilt", 0));
    std::filesystem::remove(quilt::positionsPath(folder / "quilt", 1));
    result = run((folder / "labels.png").string());
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_NE(result.err.find("positions0.exr"), std::string::npos) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

}  // namespace
}  // namespace vpe
