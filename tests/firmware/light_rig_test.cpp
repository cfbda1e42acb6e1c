// SPDX-License-Identifier: MIT
// The light's sphere, its rig (limits, smoothing, last active input wins, idle takeover) and
// the idle drift.
#include "vpe/firmware/light/light_rig.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/firmware/light/idle_drift.h"
#include "vpe/firmware/light/light_sphere.h"

namespace vpe::firmware {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kSecond = 1'000'000'000;

// A 0.2 m box centred on (0, 0.1, 0), viewer on +z.
const std::vector<float> kBox{-0.1f, 0.0f, -0.1f, 0.1f, 0.2f, 0.1f};
const std::array<float, 3> kViewer{0.0f, 0.1f, 3.0f};

InputEvent event(InputSource source, std::int64_t t, LightAction action) {
    return {source, t, action};
}

TEST(LightSphereTest, FollowsTheDocumentedFrame) {
    const LightSphere sphere(kBox, kViewer);
    EXPECT_NEAR(sphere.objectRadius(), std::sqrt(0.03), 1e-7);
    const auto front = sphere.toPosition({0, 0, 1});
    EXPECT_NEAR(front[2], 1.0, 1e-12);  // azimuth 0: toward the viewer
    EXPECT_NEAR(front[1], 0.1, 1e-7);
    const auto left = sphere.toPosition({90, 0, 1});
    EXPECT_NEAR(left[0], 1.0, 1e-12);  // +90°: counter-clockwise from above, +x
    const auto top = sphere.toPosition({0, 90, 2});
    EXPECT_NEAR(top[1], 2.1, 1e-7);
    for (const SphericalPosition p :
         {SphericalPosition{-135, 20, 0.5}, SphericalPosition{37, -10, 2},
          SphericalPosition{179, 80, 1}}) {
        const SphericalPosition back = sphere.fromPosition(sphere.toPosition(p));
        EXPECT_NEAR(back.azimuthDeg, p.azimuthDeg, 1e-9);
        EXPECT_NEAR(back.elevationDeg, p.elevationDeg, 1e-9);
        EXPECT_NEAR(back.distanceM, p.distanceM, 1e-9);
    }
    // A viewer on +x turns the frame: azimuth 0 is +x, +90° is −z.
    const LightSphere turned(kBox, {3.0f, 0.1f, 0.0f});
    EXPECT_NEAR(turned.toPosition({0, 0, 1})[0], 1.0, 1e-12);
    EXPECT_NEAR(turned.toPosition({90, 0, 1})[2], -1.0, 1e-12);
}

class LightRigTest : public ::testing::Test {
protected:
    LightRigTest() {
        light_.limits.azimuthDeg = {-90, 90};
        light_.limits.elevationDeg = {0, 80};
        light_.limits.distanceM = std::pair{0.2, 2.0};
        light_.initialElevationDeg = 30;
        light_.initialDistanceM = 1.0;
        light_.smoothingSeconds = 0.1;
        idle_.quietSeconds = 10;
        idle_.periodSeconds = 20;
        idle_.handoverSeconds = 2;
    }
    LightConfig light_;
    IdleConfig idle_;
    LightSphere sphere_{kBox, kViewer};
};

TEST_F(LightRigTest, TurnsWithinLimitsAndSmooths) {
    LightRig rig(light_, idle_, sphere_, 3, 0);
    EXPECT_EQ(rig.activeSource(), InputSource::kIdle);
    EXPECT_FALSE(rig.idle());
    EXPECT_TRUE(rig.apply(event(InputSource::kKnobs, 0, TurnLight{20, 0, 0})));
    EXPECT_EQ(rig.activeSource(), InputSource::kKnobs);
    EXPECT_EQ(rig.target().azimuthDeg, 20.0);
    rig.advance(100 * kMs);  // one time constant after the turn: 1 − 1/e of the way
    EXPECT_NEAR(rig.current().azimuthDeg, 20.0 * (1.0 - std::exp(-1.0)), 1e-9);
    rig.advance(2 * kSecond);
    EXPECT_NEAR(rig.current().azimuthDeg, 20.0, 1e-6);
    rig.apply(event(InputSource::kKnobs, 2 * kSecond, TurnLight{500, 100, 10}));
    EXPECT_EQ(rig.target().azimuthDeg, 90.0);
    EXPECT_EQ(rig.target().elevationDeg, 80.0);
    EXPECT_EQ(rig.target().distanceM, 2.0);
    rig.apply(event(InputSource::kKnobs, 2 * kSecond, ResetLight{}));
    EXPECT_EQ(rig.target().azimuthDeg, 0.0);
    EXPECT_EQ(rig.target().elevationDeg, 30.0);
    EXPECT_EQ(rig.lastEventNs(), 2 * kSecond);
}

TEST_F(LightRigTest, LastActiveInputWins) {
    LightRig rig(light_, idle_, sphere_, 3, 0);
    rig.apply(event(InputSource::kCamera, 1 * kMs, AimLight{-40.0, 50.0, std::nullopt}));
    EXPECT_EQ(rig.activeSource(), InputSource::kCamera);
    EXPECT_EQ(rig.target().azimuthDeg, -40.0);
    EXPECT_EQ(rig.target().distanceM, 1.0);
    rig.apply(event(InputSource::kKnobs, 2 * kMs, TurnLight{5, 0, 0}));
    EXPECT_EQ(rig.activeSource(), InputSource::kKnobs);
    EXPECT_EQ(rig.target().azimuthDeg, -35.0);
    rig.apply(event(InputSource::kOsc, 3 * kMs, PlaceLight{sphere_.toPosition({60, 10, 1.5})}));
    EXPECT_EQ(rig.activeSource(), InputSource::kOsc);
    EXPECT_NEAR(rig.target().azimuthDeg, 60.0, 1e-9);
    EXPECT_NEAR(rig.target().elevationDeg, 10.0, 1e-9);
    EXPECT_NEAR(rig.target().distanceM, 1.5, 1e-9);
    // A lamp that lets go while another input steers changes nothing.
    rig.apply(event(InputSource::kCamera, 4 * kMs, ReleaseLight{}));
    EXPECT_EQ(rig.activeSource(), InputSource::kOsc);
    EXPECT_FALSE(rig.idle());
}

TEST_F(LightRigTest, PresetsWrapOrRefuse) {
    LightRig rig(light_, idle_, sphere_, 3, 0);
    EXPECT_TRUE(rig.apply(event(InputSource::kKnobs, 1, SelectPreset{-1, true})));
    EXPECT_EQ(rig.preset(), 2);
    EXPECT_TRUE(rig.apply(event(InputSource::kKnobs, 2, SelectPreset{1, true})));
    EXPECT_EQ(rig.preset(), 0);
    EXPECT_TRUE(rig.apply(event(InputSource::kOsc, 3, SelectPreset{2, false})));
    EXPECT_EQ(rig.preset(), 2);
    EXPECT_FALSE(rig.apply(event(InputSource::kOsc, 4, SelectPreset{3, false})));
    EXPECT_EQ(rig.preset(), 2);
    // Choosing a material is not steering.
    EXPECT_EQ(rig.activeSource(), InputSource::kIdle);
}

TEST_F(LightRigTest, DriftsWhenQuietAndHandsBackWithoutAJump) {
    LightRig rig(light_, idle_, sphere_, 1, 0);
    rig.apply(event(InputSource::kKnobs, 0, TurnLight{-50, 0, 0}));
    std::int64_t now = 0;
    SphericalPosition previous = rig.current();
    double largestStep = 0;
    const auto step = [&](std::int64_t until) {
        for (; now < until; now += 16 * kMs) {
            rig.advance(now);
            largestStep = std::max(
                largestStep, std::abs(rig.current().azimuthDeg - previous.azimuthDeg) +
                                 std::abs(rig.current().elevationDeg - previous.elevationDeg));
            previous = rig.current();
        }
    };
    step(10 * kSecond - 20 * kMs);
    EXPECT_FALSE(rig.idle());
    EXPECT_NEAR(rig.current().azimuthDeg, -50.0, 1e-6);
    largestStep = 0;
    step(20 * kSecond);
    EXPECT_TRUE(rig.idle());
    EXPECT_EQ(rig.activeSource(), InputSource::kIdle);
    // The drift (±60° over 20 s, blended in from 50° away over 2 s: at most 1.5 × 50° / 2 s
    // = 37.5°/s plus the path's own 19°/s and 13°/s) moves under 2° per 16 ms frame: no jump.
    EXPECT_LT(largestStep, 2.0);
    EXPECT_GT(std::abs(rig.current().azimuthDeg + 50.0), 1.0);  // it moved
    // A knob turn takes over from where the drift was, relative to it.
    rig.advance(now);
    const SphericalPosition there = rig.current();
    rig.apply(event(InputSource::kKnobs, now, TurnLight{1, 0, 0}));
    EXPECT_FALSE(rig.idle());
    EXPECT_NEAR(rig.target().azimuthDeg, there.azimuthDeg + 1.0, 1e-9);
    largestStep = 0;
    step(now + kSecond);
    EXPECT_LT(largestStep, 1.0);
}

TEST_F(LightRigTest, ReleaseStartsTheDriftAtOnce) {
    LightRig rig(light_, idle_, sphere_, 1, 0);
    rig.apply(event(InputSource::kCamera, kSecond, AimLight{30.0, 40.0, std::nullopt}));
    rig.advance(2 * kSecond);
    rig.apply(event(InputSource::kCamera, 2 * kSecond, ReleaseLight{}));
    EXPECT_TRUE(rig.idle());
    const SphericalPosition held = rig.current();
    rig.advance(2 * kSecond);
    EXPECT_NEAR(rig.current().azimuthDeg, held.azimuthDeg, 1e-9);  // blends from where it was
    rig.advance(5 * kSecond);
    EXPECT_GT(std::abs(rig.current().azimuthDeg - held.azimuthDeg), 1.0);
}

TEST_F(LightRigTest, IdleDisabledHolds) {
    idle_.enabled = false;
    LightRig rig(light_, idle_, sphere_, 1, 0);
    rig.apply(event(InputSource::kCamera, 0, AimLight{30.0, 40.0, std::nullopt}));
    rig.apply(event(InputSource::kCamera, kSecond, ReleaseLight{}));
    rig.advance(100 * kSecond);
    EXPECT_FALSE(rig.idle());
    EXPECT_NEAR(rig.current().azimuthDeg, 30.0, 1e-9);
}

TEST_F(LightRigTest, FullCircleAzimuthWrapsTheShortWay) {
    light_.limits.azimuthDeg = {-180, 180};
    LightRig rig(light_, idle_, sphere_, 1, 0);
    rig.apply(event(InputSource::kOsc, 0, AimLight{170.0, std::nullopt, std::nullopt}));
    rig.advance(5 * kSecond);
    rig.apply(event(InputSource::kKnobs, 5 * kSecond, TurnLight{20, 0, 0}));
    EXPECT_NEAR(rig.target().azimuthDeg, -170.0, 1e-9);
    rig.advance(5 * kSecond + 100 * kMs);
    // 20° the short way across ±180°, not 340° back through 0°.
    const double moved = std::remainder(rig.current().azimuthDeg - 170.0, 360.0);
    EXPECT_NEAR(moved, 20.0 * (1.0 - std::exp(-1.0)), 1e-6);
}

TEST(IdleDriftTest, StaysInItsRangesAndStartsWhereTheLightWas) {
    IdleConfig config;
    config.azimuthDeg = {-30, 50};
    config.elevationDeg = {10, 40};
    const IdleDrift drift(config);
    for (double t = 0; t < 100; t += 0.37) {
        const SphericalPosition p = drift.path(t, 1.0);
        EXPECT_GE(p.azimuthDeg, -30.0 - 1e-9);
        EXPECT_LE(p.azimuthDeg, 50.0 + 1e-9);
        EXPECT_GE(p.elevationDeg, 10.0 - 1e-9);
        EXPECT_LE(p.elevationDeg, 40.0 + 1e-9);
    }
    const SphericalPosition from{-80, 70, 1.3};
    const SphericalPosition start = drift.position(from, 0, 7.0);
    EXPECT_EQ(start.azimuthDeg, -80.0);
    EXPECT_EQ(start.elevationDeg, 70.0);
    EXPECT_EQ(start.distanceM, 1.3);
    const SphericalPosition later = drift.position(from, 5.0, 12.0);
    const SphericalPosition onPath = drift.path(12.0, 1.3);
    EXPECT_EQ(later.azimuthDeg, onPath.azimuthDeg);
    // The phase is the clock's time modulo the period (40 s by default), exactly, even for a
    // wall clock's 1.7e18 ns.
    EXPECT_DOUBLE_EQ(drift.phaseAt(85 * kSecond + 250 * kMs), 5.25);
    EXPECT_DOUBLE_EQ(drift.phaseAt(1'718'000'003'123'456'789), 3.123456789);
}

// What makes nodes agree (firmware/bus/): the light is a function of time and of the shared
// state, not of how often a node draws it.
TEST_F(LightRigTest, TheLightIsAFunctionOfTimeNotOfTheFrameRate) {
    LightRig fast(light_, idle_, sphere_, 1, 0), slow(light_, idle_, sphere_, 1, 0);
    const auto turn = event(InputSource::kKnobs, 5 * kMs, TurnLight{30, 10, 0});
    fast.apply(turn);
    slow.apply(turn);
    for (std::int64_t t = 0; t <= 400 * kMs; t += 4 * kMs) {  // 250 Hz
        fast.advance(t);
    }
    for (std::int64_t t = 0; t <= 400 * kMs; t += 20 * kMs) {  // 50 Hz
        slow.advance(t);
    }
    EXPECT_DOUBLE_EQ(fast.current().azimuthDeg, slow.current().azimuthDeg);
    EXPECT_DOUBLE_EQ(fast.current().elevationDeg, slow.current().elevationDeg);
    EXPECT_NEAR(fast.current().azimuthDeg, 30.0 * (1.0 - std::exp(-3.95)), 1e-9);
}

TEST_F(LightRigTest, FollowsANewerSharedStateAndDrawsTheSameLight) {
    LightRig steered(light_, idle_, sphere_, 3, 0), follower(light_, idle_, sphere_, 3, 0);
    steered.advance(40 * kMs);
    steered.apply(event(InputSource::kKnobs, 50 * kMs, TurnLight{-25, 5, 0}));
    steered.apply(event(InputSource::kKnobs, 60 * kMs, SelectPreset{2, false}));
    const SharedLight state = steered.shared();
    EXPECT_EQ(state.moveStartNs, 50 * kMs);
    EXPECT_EQ(state.revisionNs, 60 * kMs);
    ASSERT_TRUE(state.driftAtNs.has_value());
    EXPECT_EQ(*state.driftAtNs, 10 * kSecond + 50 * kMs);  // quiet_s after the move
    EXPECT_EQ(state.steeredBy, InputSource::kKnobs);
    // The follower hears of it late: it still draws what the steered node draws.
    follower.advance(30 * kMs);
    EXPECT_TRUE(follower.apply(event(InputSource::kBus, 90 * kMs, FollowLight{state})));
    EXPECT_EQ(follower.preset(), 2);
    EXPECT_EQ(follower.activeSource(), InputSource::kBus);
    for (const std::int64_t t : {100 * kMs, 300 * kMs, 10 * kSecond + 900 * kMs, 31 * kSecond}) {
        steered.advance(t);
        follower.advance(t);
        EXPECT_DOUBLE_EQ(steered.current().azimuthDeg, follower.current().azimuthDeg) << t;
        EXPECT_DOUBLE_EQ(steered.current().elevationDeg, follower.current().elevationDeg) << t;
    }
    EXPECT_TRUE(follower.idle());  // the drift began at the time the state said, on both
    EXPECT_EQ(follower.activeSource(), InputSource::kIdle);
    // Its own echo, or anything older, changes nothing.
    SharedLight older = state;
    older.target.azimuthDeg = 80;
    EXPECT_TRUE(follower.apply(event(InputSource::kBus, 32 * kSecond, FollowLight{older})));
    EXPECT_EQ(follower.staleStates(), 1u);
    follower.advance(32 * kSecond);
    steered.advance(32 * kSecond);
    EXPECT_DOUBLE_EQ(steered.current().azimuthDeg, follower.current().azimuthDeg);
}

TEST_F(LightRigTest, ASharedMoveStartsAFrameAfterItsEvent) {
    LightRig rig(light_, idle_, sphere_, 1, 0);
    rig.setMoveLead(16 * kMs);
    rig.advance(10 * kMs);
    rig.apply(event(InputSource::kKnobs, 12 * kMs, TurnLight{10, 0, 0}));
    EXPECT_EQ(rig.shared().moveStartNs, 28 * kMs);
    rig.advance(20 * kMs);  // a frame presented before the move starts: unmoved
    EXPECT_EQ(rig.current().azimuthDeg, 0.0);
    rig.advance(128 * kMs);
    EXPECT_NEAR(rig.current().azimuthDeg, 10.0 * (1.0 - std::exp(-1.0)), 1e-9);
    rig.apply(event(InputSource::kCamera, 130 * kMs, ReleaseLight{}));  // not the steering one
    EXPECT_FALSE(rig.shared().driftAtNs.has_value() && *rig.shared().driftAtNs < kSecond);
    rig.apply(event(InputSource::kCamera, 131 * kMs, AimLight{5.0, std::nullopt, std::nullopt}));
    rig.apply(event(InputSource::kCamera, 140 * kMs, ReleaseLight{}));
    EXPECT_EQ(*rig.shared().driftAtNs, 156 * kMs);
}

TEST_F(LightRigTest, NodesThatNeverHeardOfEachOtherDriftAlike) {
    // Started 3.7 s apart, never steered: after the handover both are on the clock's path.
    LightRig early(light_, idle_, sphere_, 1, 0), late(light_, idle_, sphere_, 1, 3700 * kMs);
    for (const std::int64_t t : {16 * kSecond, 23 * kSecond + 123 * kMs}) {
        early.advance(t);
        late.advance(t);
        EXPECT_TRUE(early.idle());
        EXPECT_DOUBLE_EQ(early.current().azimuthDeg, late.current().azimuthDeg);
        EXPECT_DOUBLE_EQ(early.current().elevationDeg, late.current().elevationDeg);
    }
}

TEST_F(LightRigTest, ALocalChangeIsNewerThanAnyStateSeen) {
    LightRig rig(light_, idle_, sphere_, 1, 0);
    SharedLight ahead = rig.shared();
    ahead.revisionNs = 5 * kSecond;  // from a node whose clock runs ahead
    ahead.moveStartNs = 5 * kSecond;
    rig.apply(event(InputSource::kBus, kSecond, FollowLight{ahead}));
    rig.apply(event(InputSource::kKnobs, 2 * kSecond, TurnLight{3, 0, 0}));
    EXPECT_GT(rig.revisionNs(), 5 * kSecond);
    EXPECT_EQ(rig.activeSource(), InputSource::kKnobs);
}

}  // namespace
}  // namespace vpe::firmware
