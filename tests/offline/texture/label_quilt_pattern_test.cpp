// SPDX-License-Identifier: MIT
// The `quilted` weight kind: a label map quilted keeps its bands' widths and roughly its
// coverage, deterministically, and refuses what cannot be quilted.
#include "vpe/texture/label_quilt_pattern.h"

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/segment/label_map.h"
#include "vpe/texture/streak_statistics.h"
#include "vpe/texture/weight_maps.h"

#include "support/test_data.h"

namespace vpe {
namespace {

// Label 1: diagonal bands 6 pixels across every 24 pixels (along x + y), label 0 elsewhere.
void writeDiagonalBands(const std::filesystem::path& path) {
    segment::LabelMap labels;
    labels.width = labels.height = 96;
    labels.labels = 2;
    labels.values.assign(96 * 96, 0);
    for (int y = 0; y < 96; ++y) {
        for (int x = 0; x < 96; ++x) {
            // Distance across the bands is (x + y) / √2; 6 pixels across ≈ 8.5 along x + y.
            labels.values[static_cast<std::size_t>(y) * 96 + x] = (x + y) % 34 < 8 ? 1 : 0;
        }
    }
    segment::writeLabelImage(path, labels);
}

TEST(LabelQuiltPattern, KeepsTheBandsWidthsAndCoverage) {
    const testing::TemporaryFolder folder;
    writeDiagonalBands(folder / "labels.png");
    const texture::StreakStatistics source = texture::measureLabelStreaks(folder / "labels.png", 1);
    const std::vector<texture::WeightSource> spec = texture::parseWeightSpec(
        "quilted:from=" + (folder / "labels.png").string() + ":region=1:seed=3");
    const std::vector<float> a = texture::generateWeight(spec.front(), 200, 160);
    EXPECT_EQ(a, texture::generateWeight(spec.front(), 200, 160));
    EXPECT_GE(*std::min_element(a.begin(), a.end()), 0.0f);
    EXPECT_LE(*std::max_element(a.begin(), a.end()), 1.0f);
    const texture::StreakStatistics quilted =
        texture::measureStreaks(texture::streakMaskFromWeights(a, 200, 160, false));
    std::printf("source: coverage %.3f, width %.2f; quilted: coverage %.3f, width %.2f\n",
                source.coverage, source.widthMedian, quilted.coverage, quilted.widthMedian);
    EXPECT_NEAR(quilted.coverage, source.coverage, 0.05);       // measured TBD
    EXPECT_NEAR(quilted.widthMedian, source.widthMedian, 0.5);  // measured TBD
}

TEST(LabelQuiltPattern, RefusesWhatCannotBeQuilted) {
    const testing::TemporaryFolder folder;
    writeDiagonalBands(folder / "labels.png");
    const std::string from = "quilted:from=" + (folder / "labels.png").string();
    auto generate = [](const std::string& spec) {
        texture::generateWeight(texture::parseWeightSpec(spec).front(), 64, 64);
    };
    EXPECT_THROW(texture::parseWeightSpec("quilted:region=0"), common::InputError);
    EXPECT_THROW(texture::parseWeightSpec(from), common::InputError);
    EXPECT_THROW(texture::parseWeightSpec(from + ":region=0:block=4"), common::InputError);
    EXPECT_THROW(generate(from + ":region=2"), common::InputError);
    // Labelled pixels too few for one block of 8.
    segment::LabelMap speck;
    speck.width = speck.height = 32;
    speck.labels = 2;
    speck.values.assign(32 * 32, segment::LabelMap::kNoLabel);
    for (int y = 10; y < 15; ++y) {
        for (int x = 10; x < 15; ++x) {
            speck.values[static_cast<std::size_t>(y) * 32 + x] = x < 12 ? 1 : 0;
        }
    }
    segment::writeLabelImage(folder / "speck.png", speck);
    try {
        generate("quilted:from=" + (folder / "speck.png").string() + ":region=1:block=8");
        ADD_FAILURE() << "a 5 × 5 labelled area was quilted";
    } catch (const common::InputError& error) {
        EXPECT_NE(std::string(error.what()).find("speck.png"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace vpe
