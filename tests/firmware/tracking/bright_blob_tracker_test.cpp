// SPDX-License-Identifier: MIT
// BrightBlobTracker on synthetic frames whose lamp position is known: sub-pixel accuracy with
// and without noise, glints below min_area and blobs above max_area refused, dark frames,
// padded strides, and the connected components themselves.
#include "vpe/firmware/tracking/bright_blob_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <gtest/gtest.h>

#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

namespace vpe::firmware {
namespace {

// Positions spread over the image with every kind of fractional part.
std::vector<std::pair<double, double>> samplePositions() {
    std::vector<std::pair<double, double>> positions;
    for (int i = 0; i < 25; ++i) {
        positions.emplace_back(20.0 + 11.37 * i + 0.1 * (i % 5), 15.0 + 8.13 * i + 0.17 * (i % 7));
    }
    return positions;
}

// A 3 px lamp at (x, y) added to scene: tracker finds it within half a pixel.
void expectFindsLamp(BrightBlobTracker& tracker, SyntheticLampFrame& scene, double x, double y) {
    scene.lamp = SyntheticSpot{x, y, 3.0, 255.0};
    const std::optional<Blob> blob = tracker.find(scene.render().view());
    ASSERT_TRUE(blob.has_value()) << "no blob at (" << x << ", " << y << ")";
    EXPECT_NEAR(blob->x, x, 0.5);
    EXPECT_NEAR(blob->y, y, 0.5);
}

double worstError(double noise, double radius, double peak, std::uint32_t seedBase) {
    BrightBlobTracker tracker(BlobTrackerConfig{});
    double worst = 0.0;
    std::uint32_t seed = seedBase;
    for (const auto& [x, y] : samplePositions()) {
        SyntheticLampFrame scene;
        scene.noiseSigma = noise;
        scene.seed = seed++;
        scene.lamp = SyntheticSpot{x, y, radius, peak};
        const LuminanceFrame frame = scene.render();
        const std::optional<Blob> blob = tracker.find(frame.view());
        if (!blob) {
            ADD_FAILURE() << "no blob at (" << x << ", " << y << ")";
            return INFINITY;
        }
        worst = std::max(worst, std::hypot(blob->x - x, blob->y - y));
    }
    return worst;
}

TEST(BrightBlobTrackerTest, CleanSpotWithinAFifthOfAPixel) {
    const double worst = worstError(0.0, 3.0, 255.0, 1);
    EXPECT_LT(worst, 0.2);
    std::printf("clean spot (radius 3, peak 255): worst position error %.4f px\n", worst);
}

TEST(BrightBlobTrackerTest, SaturatedSpotWithinAFifthOfAPixel) {
    // A real lamp at a short exposure: a flat 255 core with soft edges.
    const double worst = worstError(0.0, 3.0, 600.0, 1);
    EXPECT_LT(worst, 0.2);
    std::printf("saturated spot (radius 3, peak 600): worst position error %.4f px\n", worst);
}

TEST(BrightBlobTrackerTest, NoisySpotWithinHalfAPixel) {
    const double worst = worstError(4.0, 3.0, 255.0, 100);
    EXPECT_LT(worst, 0.5);
    std::printf("noisy spot (noise sigma 4): worst position error %.4f px\n", worst);
}

TEST(BrightBlobTrackerTest, ReportsAreaPeakAndLevel) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 0.0;
    scene.lamp = SyntheticSpot{100.0, 80.0, 3.0, 255.0};
    const LuminanceFrame frame = scene.render();
    int above = 0;
    for (const std::uint8_t p : frame.pixels) {
        above += p >= 200 ? 1 : 0;
    }
    const std::optional<Blob> blob = BrightBlobTracker(BlobTrackerConfig{}).find(frame.view());
    ASSERT_TRUE(blob.has_value());
    EXPECT_EQ(blob->area, above);  // the only blob: every above-level pixel
    EXPECT_EQ(blob->peak, 255);    // 16 + 255, clamped
    EXPECT_EQ(blob->level, 200);
}

TEST(BrightBlobTrackerTest, GlintsBelowMinAreaAreIgnored) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 2.0;
    // Pin-point glints: as bright as the lamp, 1–3 pixels above the level.
    scene.distractors = {
        {40.0, 40.0, 0.6, 255.0}, {250.0, 60.0, 0.7, 255.0}, {60.0, 200.0, 0.5, 255.0}};
    BlobTrackerConfig config;
    config.minArea = 6;
    BrightBlobTracker tracker(config);
    EXPECT_FALSE(tracker.find(scene.render().view()).has_value());

    // The same glints with min_area 1 are blobs: the refusal above is the area rule's.
    EXPECT_TRUE(BrightBlobTracker(BlobTrackerConfig{200, 0.0, 1, 5000})
                    .find(scene.render().view())
                    .has_value());

    expectFindsLamp(tracker, scene, 160.3, 120.6);
}

TEST(BrightBlobTrackerTest, DimDistractorsBelowTheLevelAreIgnored) {
    SyntheticLampFrame scene;
    // A lit face and a bright wall: large, below the level.
    scene.distractors = {{80.0, 100.0, 25.0, 150.0}, {250.0, 180.0, 40.0, 120.0}};
    BrightBlobTracker tracker(BlobTrackerConfig{});
    EXPECT_FALSE(tracker.find(scene.render().view()).has_value());
    expectFindsLamp(tracker, scene, 200.25, 50.75);
}

TEST(BrightBlobTrackerTest, BlobsAboveMaxAreaAreRefused) {
    SyntheticLampFrame scene;
    scene.lamp = SyntheticSpot{160.0, 120.0, 30.0, 400.0};  // the lamp against the lens
    BlobTrackerConfig config;
    config.maxArea = 2000;
    BrightBlobTracker tracker(config);
    EXPECT_FALSE(tracker.find(scene.render().view()).has_value());
    // The same blob with a larger max_area is found: the refusal is the area rule's.
    config.maxArea = 76800;
    EXPECT_TRUE(BrightBlobTracker(config).find(scene.render().view()).has_value());

    // A window (too large) and the lamp: the lamp, though the window has more light.
    scene.distractors = {{160.0, 120.0, 30.0, 400.0}};
    expectFindsLamp(tracker, scene, 30.0, 200.0);
}

TEST(BrightBlobTrackerTest, DarkAndBlackFramesHaveNoBlob) {
    BrightBlobTracker tracker(BlobTrackerConfig{});
    SyntheticLampFrame scene;
    scene.noiseSigma = 6.0;
    EXPECT_FALSE(tracker.find(scene.render().view()).has_value());
    LuminanceFrame black{320, 240, std::vector<std::uint8_t>(320 * 240, 0)};
    EXPECT_FALSE(tracker.find(black.view()).has_value());
}

TEST(BrightBlobTrackerTest, PicksTheBlobWithTheMostLight) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 0.0;
    scene.distractors = {{60.0, 60.0, 2.0, 255.0}};  // a smaller reflection of the lamp
    scene.lamp = SyntheticSpot{250.0, 170.0, 4.0, 255.0};
    const std::optional<Blob> blob =
        BrightBlobTracker(BlobTrackerConfig{}).find(scene.render().view());
    ASSERT_TRUE(blob.has_value());
    EXPECT_NEAR(blob->x, 250.0, 0.2);
    EXPECT_NEAR(blob->y, 170.0, 0.2);
}

TEST(BrightBlobTrackerTest, RelativeThresholdRaisesTheLevel) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 0.0;
    scene.lamp = SyntheticSpot{100.4, 90.6, 6.0, 255.0};
    BlobTrackerConfig config;
    config.threshold = 100;
    const std::optional<Blob> absolute = BrightBlobTracker(config).find(scene.render().view());
    config.relativeThreshold = 0.95;
    const std::optional<Blob> relative = BrightBlobTracker(config).find(scene.render().view());
    ASSERT_TRUE(absolute && relative);
    EXPECT_EQ(absolute->level, 100);
    EXPECT_EQ(relative->level, 243);  // ⌈0.95 × 255⌉
    EXPECT_LT(relative->area, absolute->area / 4);
    EXPECT_NEAR(relative->x, 100.4, 0.2);
    EXPECT_NEAR(relative->y, 90.6, 0.2);
}

TEST(BrightBlobTrackerTest, PaddedStrideIsNotRead) {
    SyntheticLampFrame scene;
    scene.lamp = SyntheticSpot{317.5, 10.25, 3.0, 255.0};  // touching the right edge
    const LuminanceFrame frame = scene.render();
    const int stride = frame.width + 32;
    // Padding full of light: read as pixels, it would join the lamp into a blob above max_area.
    std::vector<std::uint8_t> padded(static_cast<std::size_t>(stride) * frame.height, 255);
    for (int y = 0; y < frame.height; ++y) {
        std::copy_n(frame.pixels.begin() + y * frame.width, frame.width,
                    padded.begin() + y * stride);
    }
    // The last row needs no padding.
    padded.resize(padded.size() - 32);
    BrightBlobTracker tracker(BlobTrackerConfig{});
    const std::optional<Blob> expected = tracker.find(frame.view());
    const std::optional<Blob> actual =
        tracker.find(LuminanceView{frame.width, frame.height, stride, padded});
    ASSERT_TRUE(expected && actual);
    EXPECT_DOUBLE_EQ(actual->x, expected->x);
    EXPECT_DOUBLE_EQ(actual->y, expected->y);
    EXPECT_EQ(actual->area, expected->area);
}

TEST(BrightBlobTrackerTest, JoinsShapesThatMeetLate) {
    // A comb: vertical teeth that only meet in the bottom row, and a diagonal staircase that is
    // 8-connected only through corners. Each must be one component of all its pixels.
    const int width = 64;
    const int height = 40;
    std::vector<std::uint8_t> pixels(width * height, 0);
    int comb = 0;
    for (int x = 2; x < 40; x += 3) {
        for (int y = 2; y < 30; ++y) {
            pixels[y * width + x] = 250;
            ++comb;
        }
    }
    for (int x = 2; x < 40; ++x) {
        if (pixels[30 * width + x] == 0) {
            pixels[30 * width + x] = 250;
            ++comb;
        }
    }
    BlobTrackerConfig config{200, 0.0, 1, 5000};
    std::optional<Blob> blob = BrightBlobTracker(config).find({width, height, width, pixels});
    ASSERT_TRUE(blob.has_value());
    EXPECT_EQ(blob->area, comb);

    std::fill(pixels.begin(), pixels.end(), 0);
    for (int i = 0; i < 30; ++i) {
        pixels[(35 - i) * width + 5 + i] = 250;  // rising to the right: joins above-right
    }
    blob = BrightBlobTracker(config).find({width, height, width, pixels});
    ASSERT_TRUE(blob.has_value());
    EXPECT_EQ(blob->area, 30);
    EXPECT_DOUBLE_EQ(blob->x, 5 + 14.5);
    EXPECT_DOUBLE_EQ(blob->y, 35 - 14.5);
}

TEST(BrightBlobTrackerTest, RefusesMalformedFramesAndConfigs) {
    BrightBlobTracker tracker(BlobTrackerConfig{});
    std::vector<std::uint8_t> bytes(100, 0);
    try {
        tracker.find({320, 240, 320, bytes});
        FAIL() << "a short buffer was read";
    } catch (const std::invalid_argument& error) {
        EXPECT_STREQ(error.what(), "luminance frame 320x240 stride 320: 100 bytes, needs 76800");
    }
    EXPECT_THROW(tracker.find({10, 10, 5, bytes}), std::invalid_argument);
    EXPECT_THROW(tracker.find({0, 10, 10, bytes}), std::invalid_argument);
    EXPECT_THROW(BrightBlobTracker(BlobTrackerConfig{0, 0.0, 4, 100}), std::invalid_argument);
    EXPECT_THROW(BrightBlobTracker(BlobTrackerConfig{200, 1.0, 4, 100}), std::invalid_argument);
    EXPECT_THROW(BrightBlobTracker(BlobTrackerConfig{200, 0.0, 10, 5}), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::firmware
