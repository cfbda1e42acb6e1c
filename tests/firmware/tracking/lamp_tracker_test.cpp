// SPDX-License-Identifier: MIT
// LampTracker end to end on synthetic frames along a known path: the directions it emits, the
// hold and release of a lost lamp (by frames and by ticks alone), the fresh start after a
// release, and frames of another size than the calibration's.
#include "vpe/firmware/tracking/lamp_tracker.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <variant>

#include <gtest/gtest.h>

#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

namespace vpe::firmware {
namespace {

constexpr std::int64_t kStartNs = 5'000'000'000'000;  // an uptime of 5000 s
constexpr std::int64_t kFrameNs = 40'000'000;         // 25 frames per second

// The room's true map from image to light direction (a quadratic, as a wide lens gives).
LightDirection trueDirection(double u, double v) {
    return {-40.0 + 0.3 * u - 0.02 * v + 4e-4 * u * u - 3e-4 * u * v + 1e-4 * v * v,
            70.0 + 0.01 * u - 0.3 * v - 2e-4 * u * u + 5e-4 * u * v + 3e-4 * v * v};
}

// Calibrated as the README says: the lamp at nine known directions, the image positions read.
LampCalibration calibration() {
    std::vector<CalibrationPoint> points;
    for (const double u : {30.0, 160.0, 290.0}) {
        for (const double v : {25.0, 120.0, 215.0}) {
            const LightDirection d = trueDirection(u, v);
            points.push_back({u, v, d.azimuthDeg, d.elevationDeg});
        }
    }
    return LampCalibration::fit(points);
}

LampTrackerSettings settings() {
    LampTrackerSettings s;
    s.filter = OneEuroParameters{1.0, 0.05, 1.0};
    s.holdSeconds = 0.5;
    return s;
}

LuminanceFrame frameWithLamp(double x, double y, std::uint32_t seed) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 3.0;
    scene.seed = seed;
    scene.lamp = SyntheticSpot{x, y, 3.0, 400.0};
    scene.distractors = {{60.0, 200.0, 12.0, 90.0}, {280.0, 40.0, 0.6, 255.0}};
    return scene.render();
}

LuminanceFrame emptyFrame(std::uint32_t seed) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 3.0;
    scene.seed = seed;
    return scene.render();
}

const AimLight& aimOf(const InputEvent& event) {
    const AimLight* aim = std::get_if<AimLight>(&event.action);
    if (aim == nullptr || !aim->azimuthDeg || !aim->elevationDeg) {
        throw std::runtime_error("not an AimLight with azimuth and elevation");
    }
    return *aim;
}

TEST(LampTrackerTest, FollowsALampAlongAKnownPath) {
    LampTracker tracker(settings(), calibration());
    std::vector<InputEvent> events;
    const int moving = 100;  // 4 s along a Lissajous figure, then 1 s still
    const int frames = moving + 25;
    double worstMoving = 0.0;
    double worstStill = 0.0;
    for (int i = 0; i < frames; ++i) {
        const double t = std::min(i, moving) * (kFrameNs * 1e-9);
        const double x = 160.0 + 110.0 * std::sin(2.0 * std::numbers::pi * 0.25 * t);
        const double y = 120.0 + 70.0 * std::sin(2.0 * std::numbers::pi * 0.5 * t);
        const std::int64_t timestampNs = kStartNs + i * kFrameNs;
        events.clear();
        tracker.onFrame(frameWithLamp(x, y, static_cast<std::uint32_t>(i + 1)).view(), timestampNs,
                        events);
        ASSERT_EQ(events.size(), 1u) << "frame " << i;
        EXPECT_EQ(events[0].source, InputSource::kCamera);
        EXPECT_EQ(events[0].timestampNs, timestampNs);
        const AimLight& aim = aimOf(events[0]);
        EXPECT_FALSE(aim.distanceM.has_value());
        const LightDirection expected = trueDirection(x, y);
        const double error = std::hypot(*aim.azimuthDeg - expected.azimuthDeg,
                                        *aim.elevationDeg - expected.elevationDeg);
        if (i < moving) {
            worstMoving = std::max(worstMoving, error);
        } else if (i >= moving + 15) {
            worstStill = std::max(worstStill, error);
        }
        EXPECT_TRUE(tracker.steering());
    }
    // In motion (up to ~190 px/s, ~60°/s) the One Euro filter's lag dominates.
    EXPECT_LT(worstMoving, 2.5);
    // Still for 0.6 s: the filter has settled on the lamp.
    EXPECT_LT(worstStill, 0.15);
    std::printf("path: worst direction error %.3f deg moving, %.4f deg still\n", worstMoving,
                worstStill);
}

TEST(LampTrackerTest, HoldsThenReleasesOnce) {
    LampTracker tracker(settings(), calibration());
    std::vector<InputEvent> events;
    for (int i = 0; i < 30; ++i) {
        tracker.onFrame(frameWithLamp(100.0, 100.0, static_cast<std::uint32_t>(i + 1)).view(),
                        kStartNs + i * kFrameNs, events);
    }
    ASSERT_EQ(events.size(), 30u);
    const std::int64_t lastSeenNs = kStartNs + 29 * kFrameNs;
    int releasedAt = -1;
    for (int i = 30; i < 80; ++i) {
        events.clear();
        tracker.onFrame(emptyFrame(static_cast<std::uint32_t>(1000 + i)).view(),
                        kStartNs + i * kFrameNs, events);
        tracker.tick(kStartNs + i * kFrameNs + kFrameNs / 2, events);  // a tick between frames
        if (events.empty()) {
            continue;
        }
        ASSERT_EQ(events.size(), 1u);
        ASSERT_TRUE(std::holds_alternative<ReleaseLight>(events[0].action));
        EXPECT_EQ(events[0].source, InputSource::kCamera);
        EXPECT_EQ(events[0].timestampNs, lastSeenNs + 500'000'000);
        ASSERT_EQ(releasedAt, -1) << "released twice";
        releasedAt = i;
        EXPECT_FALSE(tracker.steering());
    }
    // The hold ends 0.5 s after frame 29: at frame 41.5, noticed by the tick after frame 41.
    EXPECT_EQ(releasedAt, 41);
}

TEST(LampTrackerTest, TicksReleaseWhenFramesStop) {
    LampTracker tracker(settings(), calibration());
    std::vector<InputEvent> events;
    for (int i = 0; i < 10; ++i) {
        tracker.onFrame(frameWithLamp(200.0, 60.0, static_cast<std::uint32_t>(i + 1)).view(),
                        kStartNs + i * kFrameNs, events);
    }
    events.clear();
    const std::int64_t lastSeenNs = kStartNs + 9 * kFrameNs;
    tracker.tick(lastSeenNs + 499'999'999, events);
    EXPECT_TRUE(events.empty());
    EXPECT_TRUE(tracker.steering());
    tracker.tick(lastSeenNs + 500'000'000, events);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_TRUE(std::holds_alternative<ReleaseLight>(events[0].action));
    EXPECT_EQ(events[0].timestampNs, lastSeenNs + 500'000'000);
    tracker.tick(lastSeenNs + 2'000'000'000, events);
    EXPECT_EQ(events.size(), 1u);  // once
}

TEST(LampTrackerTest, ResumesWithoutSmoothingFromAStalePosition) {
    const LampCalibration map = calibration();
    const auto firstAimAfterGap = [&map](int gapFrames, double& distanceFromTruth) {
        LampTracker tracker(settings(), map);
        std::vector<InputEvent> events;
        int i = 0;
        for (; i < 20; ++i) {
            tracker.onFrame(frameWithLamp(40.0, 40.0, static_cast<std::uint32_t>(i + 1)).view(),
                            kStartNs + i * kFrameNs, events);
        }
        for (int gap = 0; gap < gapFrames; ++gap, ++i) {
            tracker.onFrame(emptyFrame(static_cast<std::uint32_t>(500 + i)).view(),
                            kStartNs + i * kFrameNs, events);
        }
        events.clear();
        const LuminanceFrame frame = frameWithLamp(280.0, 200.0, 77);
        tracker.onFrame(frame.view(), kStartNs + i * kFrameNs, events);
        if (events.size() != 1) {
            throw std::runtime_error("expected one event after the gap");
        }
        // Where this frame's blob maps to, unsmoothed.
        const std::optional<Blob> blob = BrightBlobTracker(settings().blob).find(frame.view());
        const LightDirection unsmoothed = map.direction(blob->x, blob->y);
        const AimLight& aim = aimOf(events[0]);
        distanceFromTruth = std::hypot(*aim.azimuthDeg - unsmoothed.azimuthDeg,
                                       *aim.elevationDeg - unsmoothed.elevationDeg);
        return tracker.steering();
    };
    double afterRelease = 0.0;
    double withinHold = 0.0;
    EXPECT_TRUE(firstAimAfterGap(20, afterRelease));  // 0.8 s gap: released, then resumed
    EXPECT_TRUE(firstAimAfterGap(5, withinHold));     // 0.2 s gap: held, still smoothing
    EXPECT_LT(afterRelease, 1e-9);                    // a fresh start: exactly where the lamp is
    // Smoothing from where it was: behind the jump (β makes the 1€ filter follow a fast jump
    // most of the way in one frame, not all of it).
    EXPECT_GT(withinHold, 0.5);
    std::printf(
        "first aim after the lamp jumped: %.2g deg off after a release, %.3f deg after "
        "a gap within the hold\n",
        afterRelease, withinHold);
}

TEST(LampTrackerTest, RescalesFramesOfAnotherSize) {
    // A camera that delivered 640 × 480 for a 320 × 240 calibration.
    LampTracker small(settings(), calibration());
    LampTracker large(settings(), calibration());
    std::vector<InputEvent> fromSmall;
    std::vector<InputEvent> fromLarge;
    SyntheticLampFrame scene;
    scene.noiseSigma = 0.0;
    scene.lamp = SyntheticSpot{123.4, 87.6, 3.0, 400.0};
    small.onFrame(scene.render().view(), kStartNs, fromSmall);
    scene.width = 640;
    scene.height = 480;
    scene.lamp = SyntheticSpot{2 * 123.4 + 0.5, 2 * 87.6 + 0.5, 6.0, 400.0};
    large.onFrame(scene.render().view(), kStartNs, fromLarge);
    ASSERT_EQ(fromSmall.size(), 1u);
    ASSERT_EQ(fromLarge.size(), 1u);
    const LightDirection truth = trueDirection(123.4, 87.6);
    EXPECT_NEAR(*aimOf(fromLarge[0]).azimuthDeg, truth.azimuthDeg, 0.05);
    EXPECT_NEAR(*aimOf(fromLarge[0]).elevationDeg, truth.elevationDeg, 0.05);
    EXPECT_NEAR(*aimOf(fromSmall[0]).azimuthDeg, truth.azimuthDeg, 0.08);
}

TEST(LampTrackerTest, RefusesInvalidSettings) {
    LampTrackerSettings bad = settings();
    bad.holdSeconds = 0.0;
    EXPECT_THROW(LampTracker(bad, calibration()), std::invalid_argument);
    bad = settings();
    bad.width = 0;
    EXPECT_THROW(LampTracker(bad, calibration()), std::invalid_argument);
    bad = settings();
    bad.blob.threshold = 300;
    EXPECT_THROW(LampTracker(bad, calibration()), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::firmware
