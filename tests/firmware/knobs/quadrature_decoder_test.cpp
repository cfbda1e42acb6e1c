// SPDX-License-Identifier: MIT
// QuadratureDecoder: clean turns both ways at 4, 2 and 1 steps per detent, reversals half way,
// chatter at a detent, a skipped state, and encoders resting with both contacts low.
#include "vpe/firmware/knobs/quadrature_decoder.h"

#include <array>
#include <vector>

#include <gtest/gtest.h>

namespace vpe::firmware::knobs {
namespace {

// The clockwise cycle from rest, (A, B): 11 → 01 → 00 → 10 → 11.
constexpr std::array<std::array<bool, 2>, 4> kCycle = {
    {{true, true}, {false, true}, {false, false}, {true, false}}};

// Walks `transitions` steps (sign: direction) from `phase`, one edge each, timestamps 1, 2, …
// after `t`; returns the detents reported, in order.
std::vector<Detent> walk(QuadratureDecoder& decoder, int& phase, int transitions, std::int64_t& t) {
    std::vector<Detent> detents;
    const int direction = transitions > 0 ? 1 : -1;
    for (int i = 0; i < std::abs(transitions); ++i) {
        phase = (phase + direction + 4) % 4;
        if (auto detent = decoder.update(kCycle[phase][0], kCycle[phase][1], ++t)) {
            detents.push_back(*detent);
        }
    }
    return detents;
}

TEST(QuadratureDecoderTest, CleanTurnsBothWaysAtEachStepsPerDetent) {
    for (const int steps : {4, 2, 1}) {
        SCOPED_TRACE(steps);
        QuadratureDecoder decoder(steps);
        EXPECT_EQ(decoder.stepsPerDetent(), steps);
        int phase = 0;
        std::int64_t t = 0;
        // Three full cycles clockwise: 12 transitions, 12 / steps detents of +1, each stamped
        // with the edge that completed it (every steps-th edge).
        std::vector<Detent> cw = walk(decoder, phase, 12, t);
        ASSERT_EQ(cw.size(), static_cast<std::size_t>(12 / steps));
        for (std::size_t i = 0; i < cw.size(); ++i) {
            EXPECT_EQ(cw[i].direction, 1);
            EXPECT_EQ(cw[i].timestampNs, static_cast<std::int64_t>((i + 1) * steps));
        }
        EXPECT_EQ(decoder.detents(), 12 / steps);
        // And back counter-clockwise through 5 cycles.
        std::vector<Detent> ccw = walk(decoder, phase, -20, t);
        ASSERT_EQ(ccw.size(), static_cast<std::size_t>(20 / steps));
        for (const Detent& detent : ccw) {
            EXPECT_EQ(detent.direction, -1);
        }
        EXPECT_EQ(decoder.detents(), -8 / steps);
        EXPECT_EQ(decoder.transitions(), -8);
    }
}

TEST(QuadratureDecoderTest, ClockwiseIsALeadingFallOfA) {
    QuadratureDecoder decoder(4);
    EXPECT_FALSE(decoder.update(false, true, 1));                        // A falls first
    EXPECT_FALSE(decoder.update(false, false, 2));                       // then B
    EXPECT_FALSE(decoder.update(true, false, 3));                        // A rises
    const std::optional<Detent> detent = decoder.update(true, true, 4);  // B rises: home
    ASSERT_TRUE(detent.has_value());
    EXPECT_EQ(detent->direction, 1);
    EXPECT_EQ(detent->timestampNs, 4);
}

TEST(QuadratureDecoderTest, TurningBackHalfWayReportsNothing) {
    QuadratureDecoder decoder(4);
    int phase = 0;
    std::int64_t t = 0;
    for (const int part : {1, 2, 3}) {
        EXPECT_TRUE(walk(decoder, phase, part, t).empty());
        EXPECT_TRUE(walk(decoder, phase, -part, t).empty());
        EXPECT_TRUE(walk(decoder, phase, -part, t).empty());
        EXPECT_TRUE(walk(decoder, phase, part, t).empty());
    }
    EXPECT_EQ(decoder.detents(), 0);
    // Three steps on, one back, two on: one detent.
    EXPECT_TRUE(walk(decoder, phase, 3, t).empty());
    EXPECT_TRUE(walk(decoder, phase, -1, t).empty());
    EXPECT_EQ(walk(decoder, phase, 2, t).size(), 1U);
}

TEST(QuadratureDecoderTest, ChatterOnTheLastContactReportsTheDetentOnce) {
    QuadratureDecoder decoder(4);
    EXPECT_FALSE(decoder.update(false, true, 1));
    EXPECT_FALSE(decoder.update(false, false, 2));
    EXPECT_FALSE(decoder.update(true, false, 3));
    // B closes to rest with bounce: 10 → 11 → 10 → 11 → 10 → 11.
    int reported = 0;
    for (int i = 0; i < 5; ++i) {
        if (auto detent = decoder.update(true, i % 2 == 0, 4 + i)) {
            reported += detent->direction;
            EXPECT_EQ(detent->timestampNs, 4);  // the first arrival
        }
    }
    EXPECT_EQ(reported, 1);
    EXPECT_EQ(decoder.detents(), 1);
    // Chatter on A at rest (the start of the next turn, abandoned): nothing.
    for (int i = 0; i < 6; ++i) {
        EXPECT_FALSE(decoder.update(i % 2 == 1, true, 10 + i));
    }
    EXPECT_EQ(decoder.detents(), 1);
}

TEST(QuadratureDecoderTest, ARepeatedLevelIsNoTransition) {
    QuadratureDecoder decoder(1);
    EXPECT_FALSE(decoder.update(true, true, 1));
    EXPECT_TRUE(decoder.update(false, true, 2));
    EXPECT_FALSE(decoder.update(false, true, 3));
    EXPECT_EQ(decoder.transitions(), 1);
}

TEST(QuadratureDecoderTest, ASkippedStateContinuesTheLastDirection) {
    QuadratureDecoder decoder(4);
    EXPECT_FALSE(decoder.update(false, true, 1));  // +1
    EXPECT_FALSE(decoder.update(true, false, 2));  // 01 → 10: both changed, taken as +2
    EXPECT_EQ(decoder.transitions(), 3);
    const std::optional<Detent> detent = decoder.update(true, true, 3);
    ASSERT_TRUE(detent.has_value());
    EXPECT_EQ(detent->direction, 1);

    QuadratureDecoder backwards(4);
    EXPECT_FALSE(backwards.update(true, false, 1));  // −1
    EXPECT_FALSE(backwards.update(false, true, 2));  // skipped: −2
    EXPECT_EQ(backwards.update(true, true, 3)->direction, -1);
}

// Encoders wired active-high (pull-downs) rest at 00: the initial levels are the rest.
TEST(QuadratureDecoderTest, CountsFromTheRestItStartsIn) {
    QuadratureDecoder decoder(4, false, false);
    int phase = 2;  // 00 in the cycle
    std::int64_t t = 0;
    const std::vector<Detent> detents = walk(decoder, phase, 8, t);
    ASSERT_EQ(detents.size(), 2U);
    EXPECT_EQ(detents[0].timestampNs, 4);
    EXPECT_EQ(phase, 2);
}

TEST(QuadratureDecoderTest, UnsupportedStepsPerDetentMeanAFullCycle) {
    EXPECT_EQ(QuadratureDecoder(3).stepsPerDetent(), 4);
    EXPECT_EQ(QuadratureDecoder(0).stepsPerDetent(), 4);
}

}  // namespace
}  // namespace vpe::firmware::knobs
