// SPDX-License-Identifier: MIT
// The structured-light sequence: its order, its levels, and that its Gray bits and phase steps
// encode every projector coordinate.
#include "vpe/proto/structured_light.h"

#include <cmath>
#include <set>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(StructuredLight, GrayCodeRoundTripsAndNeighboursDifferInOneBit) {
    for (std::uint32_t value = 0; value < 5000; ++value) {
        EXPECT_EQ(grayDecode(grayEncode(value)), value);
        const std::uint32_t changed = grayEncode(value) ^ grayEncode(value + 1);
        EXPECT_EQ(changed & (changed - 1), 0u) << value;  // one bit
    }
}

TEST(StructuredLight, OrdersFlatFieldsThenGrayPairsThenPhasePerAxis) {
    const StructuredLightSequence sequence({1920, 1080, 32, 8});
    EXPECT_EQ(sequence.grayBits(PatternAxis::kColumns), 11);
    EXPECT_EQ(sequence.grayBits(PatternAxis::kRows), 11);
    EXPECT_EQ(sequence.lowestGrayBit(), 3);
    const auto& p = sequence.patterns();
    ASSERT_EQ(p.size(), 2u + 2 * (2 * 8 + 8));
    EXPECT_EQ(p[0].name(), "white");
    EXPECT_EQ(p[1].name(), "black");
    EXPECT_EQ(p[2].name(), "gray-x-b10");
    EXPECT_EQ(p[3].name(), "gray-x-b10-inv");
    EXPECT_EQ(p[17].name(), "gray-x-b3-inv");
    EXPECT_EQ(p[18].name(), "phase-x-s0");
    EXPECT_EQ(p[26].name(), "gray-y-b10");
    EXPECT_EQ(p.back().name(), "phase-y-s7");
    std::set<std::string> names;
    for (const PatternSpec& pattern : p) {
        EXPECT_TRUE(names.insert(pattern.name()).second) << pattern.name();
        EXPECT_EQ(sequence.find(pattern.name()), static_cast<int>(names.size()) - 1);
    }
    EXPECT_EQ(sequence.find("gray-x-b2"), -1);
}

TEST(StructuredLight, GrayBitsAndPhaseTogetherGiveEveryColumn) {
    const StructuredLightSequence sequence({640, 360, 16, 4});
    for (int x = 0; x < 640; ++x) {
        std::uint32_t gray = 0;
        for (const PatternSpec& pattern : sequence.patterns()) {
            if (pattern.kind == PatternKind::kGray && pattern.axis == PatternAxis::kColumns &&
                !pattern.inverted) {
                const double level = sequence.level(pattern, x, 7);
                PatternSpec inverse = pattern;
                inverse.inverted = true;
                EXPECT_EQ(level + sequence.level(inverse, x, 7), 1.0);
                gray |= (level > 0.5 ? 1u : 0u) << (pattern.bit - sequence.lowestGrayBit());
            }
        }
        // The Gray bits give the quarter period; the phase the place inside the period.
        const std::uint32_t quarter = grayDecode(gray);
        EXPECT_EQ(quarter, static_cast<std::uint32_t>(x) >> 2);
        double sine = 0, cosine = 0;
        for (int s = 0; s < 4; ++s) {
            const double level =
                sequence.level({PatternKind::kPhase, PatternAxis::kColumns, 0, false, s}, x, 0);
            sine += level * std::sin(2 * kPi * s / 4);
            cosine += level * std::cos(2 * kPi * s / 4);
        }
        double angle = std::atan2(sine, cosine);
        angle += angle < 0 ? 2 * kPi : 0;
        EXPECT_NEAR(std::remainder(angle / (2 * kPi) * 16 - x % 16, 16.0), 0.0, 1e-9) << x;
    }
}

TEST(StructuredLight, RowsPatternsVaryAlongColumnsOnly) {
    const StructuredLightSequence sequence({64, 48, 8, 3});
    std::vector<std::uint8_t> codes(64 * 48);
    const PatternSpec pattern{PatternKind::kPhase, PatternAxis::kRows, 0, false, 1};
    sequence.render(pattern, codes);
    for (int y = 0; y < 48; ++y) {
        for (int x = 0; x < 64; ++x) {
            EXPECT_EQ(codes[static_cast<std::size_t>(y * 64 + x)], sequence.code(pattern, 0, y));
        }
    }
    EXPECT_THROW(sequence.render(pattern, std::span<std::uint8_t>(codes).first(10)),
                 StructuredLightError);
}

TEST(StructuredLight, RefusesParametersThatMakeNoSequence) {
    EXPECT_THROW(StructuredLightSequence({4, 100, 8, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 24, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 4, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 32, 2}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({64, 16, 32, 8}), StructuredLightError);
    try {
        StructuredLightSequence({640, 480, 24, 8});
    } catch (const StructuredLightError& error) {
        EXPECT_STREQ(error.what(), "phase period 24 is not a power of two in 8..1024");
    }
}

}  // namespace
}  // namespace vpe::proto
