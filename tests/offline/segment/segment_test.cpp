// SPDX-License-Identifier: MIT
// Segmentation: seeded labelling in colour and in appearance, island removal, label order,
// k-means and the choice of K, the comparison with a reference (Hungarian matching), the
// label files, and the seed picker the reports use.
#include <algorithm>
#include <array>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/segment/kmeans.h"
#include "vpe/segment/label_comparison.h"
#include "vpe/segment/label_map.h"
#include "vpe/segment/segmentation.h"

#include "support/label_seeds.h"
#include "support/test_data.h"

namespace vpe {
namespace {

// An appearance made by hand: each pixel's CIELAB colour and features come from `material`,
// plus a little noise. Features: 3 colour values, then one "gloss" value.
segment::Appearance makeAppearance(int width, int height,
                                   const std::vector<std::array<float, 4>>& materials,
                                   const std::function<int(int x, int y)>& material,
                                   float noise = 0.01f) {
    segment::Appearance a;
    a.width = width;
    a.height = height;
    const std::size_t pixels = static_cast<std::size_t>(width) * height;
    a.valid.assign(pixels, 1);
    a.validPixels = pixels;
    a.average.assign(pixels * 3, 0.2f);
    a.lab.assign(pixels * 3, 0.0f);
    a.featureCount = 4;
    a.features.assign(pixels * 4, 0.0f);
    std::mt19937 random(5);
    std::normal_distribution<float> jitter(0.0f, noise);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = a.pixel(x, y);
            const std::array<float, 4>& m = materials[static_cast<std::size_t>(material(x, y))];
            for (int c = 0; c < 3; ++c) {
                a.lab[p * 3 + c] = 50.0f * m[static_cast<std::size_t>(c)] + jitter(random);
                a.average[p * 3 + c] = 0.1f + 0.5f * m[static_cast<std::size_t>(c)];
            }
            for (int f = 0; f < 4; ++f) {
                a.features[p * 4 + f] = m[static_cast<std::size_t>(f)] + jitter(random);
            }
        }
    }
    return a;
}

segment::LabelMap mapOf(int width, int height, const std::function<int(int x, int y)>& label) {
    segment::LabelMap map;
    map.width = width;
    map.height = height;
    map.values.resize(static_cast<std::size_t>(width) * height);
    int highest = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const int value = label(x, y);
            map.values[static_cast<std::size_t>(y) * width + x] = static_cast<std::uint8_t>(value);
            if (value != segment::LabelMap::kNoLabel) {
                highest = std::max(highest, value);
            }
        }
    }
    map.labels = highest + 1;
    return map;
}

// Left third material 0, middle third 1 (same colour as 0, glossier), right third 2.
const std::vector<std::array<float, 4>> kThreeMaterials = {
    {{0.2f, 0.5f, 0.5f, 0.0f}}, {{0.2f, 0.5f, 0.5f, 1.0f}}, {{0.9f, 0.3f, 0.6f, 0.0f}}};
int thirds(int x, int) {
    return x < 10 ? 0 : x < 20 ? 1 : 2;
}

TEST(SeededSegmentation, AppearanceSeparatesMaterialsOfOneColourThatColourCannot) {
    const segment::Appearance appearance = makeAppearance(30, 12, kThreeMaterials, thirds);
    const std::vector<segment::PixelSeed> seeds{{4, 5}, {15, 5}, {25, 5}};
    const segment::LabelMap truth = mapOf(30, 12, thirds);
    const segment::LabelMap byAppearance =
        segment::labelBySeeds(appearance, seeds, segment::SeedSpace::kAppearance);
    EXPECT_EQ(byAppearance.labels, 3);
    EXPECT_DOUBLE_EQ(segment::compareLabels(byAppearance, truth).meanIou, 1.0);
    // In colour alone, materials 0 and 1 are one: their pixels split between the two seeds by
    // noise, so at least one of them is badly recovered.
    const segment::LabelComparison byColour = segment::compareLabels(
        segment::labelBySeeds(appearance, seeds, segment::SeedSpace::kColour), truth);
    EXPECT_LT(std::min(byColour.iou[0], byColour.iou[1]), 0.8);
    EXPECT_DOUBLE_EQ(byColour.iou[2], 1.0);
}

TEST(SeededSegmentation, LabelsFollowTheSeedsOrderAndBadSeedsAreNamed) {
    const segment::Appearance appearance = makeAppearance(30, 12, kThreeMaterials, thirds);
    segment::SegmentOptions options;
    options.seeds = {{25, 5}, {4, 5}, {15, 5}};
    const segment::SegmentResult result = segment::segmentAppearance(appearance, options);
    EXPECT_EQ(result.map.values[appearance.pixel(27, 1)], 0);
    EXPECT_EQ(result.map.values[appearance.pixel(1, 1)], 1);
    EXPECT_EQ(result.map.values[appearance.pixel(12, 11)], 2);

    options.seeds = {{4, 5}, {30, 5}};
    try {
        segment::segmentAppearance(appearance, options);
        FAIL() << "a seed outside the model was accepted";
    } catch (const common::InputError& error) {
        EXPECT_NE(std::string(error.what()).find("(30, 5)"), std::string::npos) << error.what();
    }
    segment::Appearance holes = appearance;
    holes.valid[holes.pixel(4, 5)] = 0;
    options.seeds = {{4, 5}, {25, 5}};
    EXPECT_THROW(segment::segmentAppearance(holes, options), common::InputError);
}

TEST(Islands, SmallRegionsJoinTheLabelAroundThem) {
    // A 2 × 2 speck of label 1 inside label 0, and a big region of label 1 on the right.
    segment::LabelMap map = mapOf(20, 10, [](int x, int y) {
        return (x >= 4 && x < 6 && y >= 4 && y < 6) || x >= 14 ? 1 : 0;
    });
    EXPECT_EQ(segment::removeIslands(map, 5), 1u);
    EXPECT_EQ(map.values[5 * 20 + 5], 0);
    EXPECT_EQ(map.values[5 * 20 + 15], 1);          // the big region stays
    EXPECT_EQ(segment::removeIslands(map, 5), 0u);  // nothing left to merge
}

TEST(Islands, UnlabelledPixelsStayUnlabelled) {
    segment::LabelMap map = mapOf(12, 6, [](int x, int) {
        return x < 2 ? segment::LabelMap::kNoLabel : x < 3 ? 1 : 0;
    });
    segment::removeIslands(map, 10);
    EXPECT_EQ(map.values[0], segment::LabelMap::kNoLabel);
    EXPECT_EQ(map.values[2], 0);
}

TEST(LabelOrder, ClustersAreNumberedByIncreasingLuminance) {
    const segment::Appearance appearance = makeAppearance(30, 12, kThreeMaterials, thirds);
    segment::LabelMap map = mapOf(30, 12, [](int x, int y) { return 2 - thirds(x, y); });
    segment::orderLabelsByLuminance(map, appearance);
    // Materials 0 and 1 have the same average (0.1 + 0.5 · colour); material 2 is brighter in
    // the channels luminance weighs most, so it is last.
    EXPECT_EQ(map.values[25], 2);
}

TEST(KMeans, IsDeterministicAndFindsSeparatedClusters) {
    std::vector<float> points;
    std::mt19937 random(3);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    const float centres[3][2] = {{0, 0}, {3, 0}, {0, 3}};
    for (int i = 0; i < 600; ++i) {
        points.push_back(centres[i % 3][0] + noise(random));
        points.push_back(centres[i % 3][1] + noise(random));
    }
    segment::KMeansOptions options;
    options.clusters = 3;
    const segment::KMeansResult first = segment::kMeans(points, 2, options);
    options.threads = 2;
    const segment::KMeansResult second = segment::kMeans(points, 2, options);
    EXPECT_EQ(first.labels, second.labels);
    for (int i = 3; i < 600; ++i) {
        EXPECT_EQ(first.labels[static_cast<std::size_t>(i)],
                  first.labels[static_cast<std::size_t>(i % 3)]);
    }
    const segment::ClusterCountChoice choice =
        segment::chooseClusterCount(points, 2, 2, 6, options);
    EXPECT_EQ(choice.chosen, 3);
    EXPECT_EQ(choice.candidates.size(), 5u);
}

TEST(LabelComparison, MatchesArbitraryLabelNumbers) {
    const segment::LabelMap truth = mapOf(30, 12, thirds);
    const segment::LabelMap renamed =
        mapOf(30, 12, [](int x, int y) { return (thirds(x, y) + 1) % 3; });
    const segment::LabelComparison same = segment::compareLabels(renamed, truth);
    EXPECT_DOUBLE_EQ(same.meanIou, 1.0);
    EXPECT_EQ(same.matchedLabels, (std::vector<int>{1, 2, 0}));
    // Half of region 2 predicted as region 1: IoU(1) = 10 / 15, IoU(2) = 5 / 10.
    const segment::LabelMap shifted = mapOf(30, 12, [](int x, int) {
        return x < 10 ? 0 : x < 25 ? 1 : 2;
    });
    const segment::LabelComparison partly = segment::compareLabels(shifted, truth);
    EXPECT_NEAR(partly.iou[1], 10.0 / 15.0, 1e-12);
    EXPECT_NEAR(partly.iou[2], 5.0 / 10.0, 1e-12);
    // Fewer predicted labels than reference ones: the unmatched reference label scores 0.
    const segment::LabelMap two = mapOf(30, 12, [](int x, int) { return x < 10 ? 0 : 1; });
    const segment::LabelComparison merged = segment::compareLabels(two, truth);
    EXPECT_EQ(std::count(merged.matchedLabels.begin(), merged.matchedLabels.end(), -1), 1);
}

TEST(LabelComparison, HungarianFindsTheCheapestAssignment) {
    // Greedy (row 0 takes its cheapest column, 1) ends at 1 + 9 + 3 = 13; the optimum is
    // rows → columns 1, 0, 2: 2 + 2 + 4 = 8, the only assignment that cheap.
    const std::vector<std::vector<double>> cost = {{1, 2, 9}, {2, 9, 9}, {9, 3, 4}};
    EXPECT_EQ(segment::minimumCostAssignment(cost), (std::vector<int>{1, 0, 2}));
}

TEST(LabelFiles, RoundTripAndRefuseWhatIsNotALabelImage) {
    testing::TemporaryFolder folder;
    const segment::LabelMap map = mapOf(7, 5, [](int x, int y) {
        return x == 0 && y == 0 ? segment::LabelMap::kNoLabel : (x + y) % 4;
    });
    segment::writeLabelImage(folder / "labels.png", map);
    const segment::LabelMap read = segment::readLabelImage(folder / "labels.png");
    EXPECT_EQ(read.values, map.values);
    EXPECT_EQ(read.labels, 4);
    EXPECT_THROW(segment::readLabelImage(folder / "missing.png"), common::InputError);
    EXPECT_EQ(segment::overlayPathFor("dir/labels.png"),
              std::filesystem::path("dir/labels-overlay.png"));
}

TEST(LabelSeeds, PickThePixelDeepestInsideEachRegion) {
    const segment::LabelMap map = mapOf(30, 11, thirds);
    const std::vector<segment::PixelSeed> seeds = testing::innermostPixels(map);
    ASSERT_EQ(seeds.size(), 3u);
    EXPECT_EQ(map.values[static_cast<std::size_t>(seeds[1].y) * 30 + seeds[1].x], 1);
    // Deepest possible in a 10 × 11 band: 5 pixels from its sides, 5 from the picture's edges.
    EXPECT_GE(seeds[1].x, 14);
    EXPECT_LE(seeds[1].x, 15);
    EXPECT_GE(seeds[1].y, 4);
    EXPECT_LE(seeds[1].y, 6);
    EXPECT_EQ(testing::seedsArgument({{1, 2}, {3, 4}}), "1,2;3,4");
}

}  // namespace
}  // namespace vpe
