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

// OpenCV's GrayCodePattern as procam-calibration shows it: every bit down to bit 0, no phase,
// white and black (or neither).
TEST(StructuredLight, AGrayCodeAloneGoesDownToBitZero) {
    StructuredLightParameters parameters{1024, 768, 32, 0};
    parameters.flatFields = false;
    const StructuredLightSequence sequence(parameters);
    EXPECT_FALSE(sequence.hasPhase());
    EXPECT_EQ(sequence.lowestGrayBit(), 0);
    EXPECT_EQ(sequence.grayBinWidth(), 1);
    EXPECT_EQ(sequence.grayBits(PatternAxis::kColumns), 10);
    EXPECT_EQ(sequence.grayBits(PatternAxis::kRows), 10);
    const auto& p = sequence.patterns();
    ASSERT_EQ(p.size(), 2u * 2 * 10);
    EXPECT_EQ(p[0].name(), "gray-x-b9");
    EXPECT_EQ(p[19].name(), "gray-x-b0-inv");
    EXPECT_EQ(p[20].name(), "gray-y-b9");
    EXPECT_EQ(sequence.find("white"), -1);
    EXPECT_EQ(sequence.find("phase-x-s0"), -1);
    // Every column's code read back from its bits.
    for (int x = 0; x < 1024; ++x) {
        std::uint32_t gray = 0;
        for (int bit = 0; bit < 10; ++bit) {
            gray |= (sequence.level({PatternKind::kGray, PatternAxis::kColumns, bit, false, 0}, x,
                                    0) > 0.5
                         ? 1u
                         : 0u)
                    << bit;
        }
        ASSERT_EQ(grayDecode(gray), static_cast<std::uint32_t>(x));
    }
    parameters.flatFields = true;
    EXPECT_EQ(StructuredLightSequence(parameters).patterns().size(), 42u);
}

TEST(StructuredLight, ACodeStepCountsCodesNotPixels) {
    StructuredLightParameters parameters{1920, 1080, 32, 0};
    parameters.codeStep = 3;
    parameters.lowestGrayBit = 1;
    const StructuredLightSequence sequence(parameters);
    EXPECT_EQ(sequence.grayBits(PatternAxis::kColumns), 10);  // 640 codes
    EXPECT_EQ(sequence.grayBits(PatternAxis::kRows), 9);      // 360 codes
    EXPECT_EQ(sequence.grayBinWidth(), 6);
    EXPECT_EQ(sequence.patterns().size(), 2u + 2 * (9 + 8));
    const PatternSpec bit1{PatternKind::kGray, PatternAxis::kColumns, 1, false, 0};
    for (int x = 0; x < 1920; ++x) {
        const bool lit = (grayEncode(static_cast<std::uint32_t>(x / 3)) >> 1) & 1u;
        ASSERT_EQ(sequence.level(bit1, x, 0), lit ? 1.0 : 0.0) << x;
    }
    // With a phase: bins of 3 pixels fit a quarter of 16, bins of 6 do not.
    parameters.phaseSteps = 4;
    parameters.phasePeriod = 16;
    parameters.lowestGrayBit = 0;
    EXPECT_EQ(StructuredLightSequence(parameters).grayBinWidth(), 3);
    parameters.lowestGrayBit = 1;
    EXPECT_THROW(StructuredLightSequence{parameters}, StructuredLightError);
}

TEST(StructuredLight, RefusesParametersThatMakeNoSequence) {
    EXPECT_THROW(StructuredLightSequence({4, 100, 8, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 24, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 4, 8}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({640, 480, 32, 2}), StructuredLightError);
    EXPECT_THROW(StructuredLightSequence({64, 16, 32, 8}), StructuredLightError);
    const auto refusal = [](const StructuredLightParameters& parameters) -> std::string {
        try {
            StructuredLightSequence{parameters};
        } catch (const StructuredLightError& error) {
            return error.what();
        }
        return "";
    };
    EXPECT_EQ(refusal({640, 480, 24, 8}), "phase period 24 is not a power of two in 8..1024");
    EXPECT_EQ(refusal({640, 480, 32, 2}), "phase steps 2 outside 3..64 (0: no phase images)");
    // Without a phase the period is not read.
    EXPECT_EQ(refusal({640, 480, 24, 0}), "");
    StructuredLightParameters step{640, 480, 32, 0};
    step.codeStep = 0;
    EXPECT_EQ(refusal(step),
              "code step 0 outside 1..240 (2 codes across the 480 pixels of the "
              "shorter axis)");
    step.codeStep = 241;
    EXPECT_NE(refusal(step), "");
    StructuredLightParameters lowest{640, 480, 32, 0};
    lowest.lowestGrayBit = 9;  // 480 rows: bits 0..8
    EXPECT_EQ(refusal(lowest),
              "lowest Gray bit 9 outside 0..8 (the bits of the shorter axis' code)");
    StructuredLightParameters wide{640, 480, 32, 8};
    wide.codeStep = 2;  // the default lowest bit 3 makes bins of 16 pixels
    EXPECT_EQ(refusal(wide),
              "Gray bins of 16 pixels (code step 2, lowest bit 3) are wider than "
              "a quarter of the phase period 32");
}

}  // namespace
}  // namespace vpe::proto
