// SPDX-License-Identifier: MIT
// KnobEdgeSink end to end: line edges in, InputEvents out (turns on the configured axis with
// step × acceleration, presets, reset), stamped with the edges; levels, routing, unknown lines.
#include "vpe/firmware/knobs/knob_edge_sink.h"

#include <variant>

#include <gtest/gtest.h>

namespace vpe::firmware::knobs {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr EdgeKind kRise = EdgeKind::kRising;
constexpr EdgeKind kFall = EdgeKind::kFalling;

KnobsConfig twoKnobsThreeButtons() {
    KnobsConfig config;
    config.enabled = true;
    EncoderConfig azimuth{17, 27, KnobAxis::kAzimuth, 2.5, 4, false, {}};
    azimuth.acceleration = AccelerationCurve{100, 20, 4};
    config.encoders.push_back(azimuth);
    config.encoders.push_back(EncoderConfig{5, 6, KnobAxis::kDistance, 0.05, 2, true, {}});
    config.buttons.push_back(ButtonConfig{22, ButtonAction::kNextPreset, true, 20});
    config.buttons.push_back(ButtonConfig{23, ButtonAction::kPreviousPreset, true, 20});
    config.buttons.push_back(ButtonConfig{24, ButtonAction::kReset, false, 10});
    return config;
}

// One clockwise detent of a 4-step encoder on lines a, b: A falls, B falls, A rises, B rises,
// 1 ms apart from `t`; with a bounce on A's first edge.
void clockwiseDetent(KnobEdgeSink& sink, unsigned a, unsigned b, std::int64_t t,
                     std::vector<InputEvent>& events) {
    EXPECT_TRUE(sink.onEdge({a, kFall, t}, events));
    EXPECT_TRUE(sink.onEdge({a, kRise, t + 50'000}, events));  // chatter
    EXPECT_TRUE(sink.onEdge({a, kFall, t + 100'000}, events));
    EXPECT_TRUE(sink.onEdge({b, kFall, t + 1 * kMs}, events));
    EXPECT_TRUE(sink.onEdge({a, kRise, t + 2 * kMs}, events));
    EXPECT_TRUE(sink.onEdge({b, kRise, t + 3 * kMs}, events));
}

TEST(KnobEdgeSinkTest, ADetentIsATurnOnItsAxisStampedWithTheCompletingEdge) {
    KnobEdgeSink sink(twoKnobsThreeButtons(), {}, 0);
    std::vector<InputEvent> events;
    clockwiseDetent(sink, 17, 27, 1000 * kMs, events);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].source, InputSource::kKnobs);
    EXPECT_EQ(events[0].timestampNs, 1003 * kMs);
    const TurnLight& turn = std::get<TurnLight>(events[0].action);
    EXPECT_EQ(turn.azimuthDeg, 2.5);
    EXPECT_EQ(turn.elevationDeg, 0);
    EXPECT_EQ(turn.distanceM, 0);
}

TEST(KnobEdgeSinkTest, FastDetentsAccelerate) {
    KnobEdgeSink sink(twoKnobsThreeButtons(), {}, 0);
    std::vector<InputEvent> events;
    clockwiseDetent(sink, 17, 27, 1000 * kMs, events);  // first: ×1
    clockwiseDetent(sink, 17, 27, 1010 * kMs, events);  // 10 ms later: ×4 (max)
    clockwiseDetent(sink, 17, 27, 1070 * kMs, events);  // 60 ms later: ×2.5
    clockwiseDetent(sink, 17, 27, 2000 * kMs, events);  // slow again: ×1
    ASSERT_EQ(events.size(), 4U);
    EXPECT_DOUBLE_EQ(std::get<TurnLight>(events[0].action).azimuthDeg, 2.5);
    EXPECT_DOUBLE_EQ(std::get<TurnLight>(events[1].action).azimuthDeg, 10);
    EXPECT_DOUBLE_EQ(std::get<TurnLight>(events[2].action).azimuthDeg, 6.25);
    EXPECT_DOUBLE_EQ(std::get<TurnLight>(events[3].action).azimuthDeg, 2.5);
}

TEST(KnobEdgeSinkTest, AReversedHalfStepEncoderTurnsDistanceTheOtherWay) {
    KnobEdgeSink sink(twoKnobsThreeButtons(), {}, 0);
    std::vector<InputEvent> events;
    // Two steps clockwise on lines 5/6 (2 steps per detent): one detent, reversed.
    EXPECT_TRUE(sink.onEdge({5, kFall, 10}, events));
    EXPECT_TRUE(sink.onEdge({6, kFall, 20}, events));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_DOUBLE_EQ(std::get<TurnLight>(events[0].action).distanceM, -0.05);
    EXPECT_EQ(events[0].timestampNs, 20);
    EXPECT_FALSE(sink.levels().at(5));
    EXPECT_FALSE(sink.levels().at(6));
}

TEST(KnobEdgeSinkTest, ButtonsSelectPresetsAndReset) {
    KnobEdgeSink sink(twoKnobsThreeButtons(), {}, 0);
    std::vector<InputEvent> events;
    // Next preset: press with chatter, settles 20 ms after the last change (on a tick).
    EXPECT_TRUE(sink.onEdge({22, kFall, 100 * kMs}, events));
    EXPECT_TRUE(sink.onEdge({22, kRise, 101 * kMs}, events));
    EXPECT_TRUE(sink.onEdge({22, kFall, 102 * kMs}, events));
    sink.onTick(110 * kMs, events);
    EXPECT_TRUE(events.empty());
    sink.onTick(122 * kMs, events);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(events[0].timestampNs, 102 * kMs);
    EXPECT_EQ(std::get<SelectPreset>(events[0].action).value, 1);
    EXPECT_TRUE(std::get<SelectPreset>(events[0].action).relative);
    sink.onTick(500 * kMs, events);
    EXPECT_TRUE(sink.onEdge({22, kRise, 600 * kMs}, events));  // release: nothing
    sink.onTick(700 * kMs, events);
    EXPECT_EQ(events.size(), 1U);

    // Previous preset, settled by a later edge on another line (no tick: a replay).
    events.clear();
    EXPECT_TRUE(sink.onEdge({23, kFall, 800 * kMs}, events));
    EXPECT_TRUE(sink.onEdge({17, kFall, 900 * kMs}, events));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(std::get<SelectPreset>(events[0].action).value, -1);
    EXPECT_EQ(events[0].timestampNs, 800 * kMs);

    // Reset: active-high, 10 ms.
    events.clear();
    EXPECT_TRUE(sink.onEdge({24, kRise, 1000 * kMs}, events));
    sink.onTick(1010 * kMs, events);
    ASSERT_EQ(events.size(), 1U);
    EXPECT_TRUE(std::holds_alternative<ResetLight>(events[0].action));
}

TEST(KnobEdgeSinkTest, UnknownLinesAreIgnoredAndLevelsStartIdle) {
    const KnobsConfig config = twoKnobsThreeButtons();
    KnobEdgeSink sink(config, {{22, false}}, 0);  // button 22 held at start
    const std::vector<unsigned> expected = {5, 6, 17, 22, 23, 24, 27};
    EXPECT_EQ(sink.lines(), expected);
    EXPECT_TRUE(sink.levels().at(17));
    EXPECT_FALSE(sink.levels().at(22));
    EXPECT_TRUE(sink.levels().at(23));
    EXPECT_FALSE(sink.levels().at(24));  // active-high: released is low
    std::vector<InputEvent> events;
    EXPECT_FALSE(sink.onEdge({4, kFall, 10}, events));
    sink.onTick(10'000 * kMs, events);  // the held button does not fire
    EXPECT_TRUE(events.empty());
    EXPECT_EQ(sink.levels().count(4), 0U);
}

TEST(KnobEdgeSinkTest, AMissedEventIsRepairedByTheNextEdgesKind) {
    KnobsConfig config;
    config.encoders.push_back(EncoderConfig{17, 27, KnobAxis::kElevation, 1, 4, false, {}});
    KnobEdgeSink sink(config, {}, 0);
    std::vector<InputEvent> events;
    // A falls, B falls, [A's rise lost], A falls again (repeated level: no transition)...
    EXPECT_TRUE(sink.onEdge({17, kFall, 1}, events));
    EXPECT_TRUE(sink.onEdge({27, kFall, 2}, events));
    EXPECT_TRUE(sink.onEdge({17, kFall, 3}, events));
    // ...then the turn goes on: A rises, B rises: home, one detent.
    EXPECT_TRUE(sink.onEdge({17, kRise, 4}, events));
    EXPECT_TRUE(sink.onEdge({27, kRise, 5}, events));
    ASSERT_EQ(events.size(), 1U);
    EXPECT_EQ(std::get<TurnLight>(events[0].action).elevationDeg, 1);
}

}  // namespace
}  // namespace vpe::firmware::knobs
