// SPDX-License-Identifier: MIT
// ScanFrameCheck on synthetic captures: a camera that sees the projector pixel for pixel (a
// strip at the right in shadow), with a projector gamma, a black level and noise. Every
// pattern of a clean capture passes; a stale white, a stale inverse, a stale Gray pattern, a
// blend of two patterns and a repeated phase step are each refused with their problem; a
// group given again after a refusal passes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/firmware/scan/frame_check.h"
#include "vpe/proto/structured_light.h"

namespace vpe::firmware {
namespace {

constexpr int kWidth = 64, kHeight = 32;
constexpr int kLitColumns = 56;  // columns 56..63 are in shadow

proto::StructuredLightParameters parameters() {
    proto::StructuredLightParameters p;
    p.width = kWidth;
    p.height = kHeight;
    p.phasePeriod = 8;
    p.phaseSteps = 4;
    return p;
}

// The camera's image of pattern `index`: black 12, white 220 (levels through a 2.2 gamma),
// noise of ±2 from a hash of the pixel and `seed`.
CameraImage captureOf(const proto::StructuredLightSequence& sequence, std::size_t index,
                      std::uint32_t seed = 1) {
    CameraImage image;
    image.width = kWidth;
    image.height = kHeight;
    image.maxValue = 255;
    image.samples.resize(image.pixelCount());
    const proto::PatternSpec& pattern = sequence.patterns()[index];
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const double level = x < kLitColumns ? sequence.level(pattern, x, y) : 0.0;
            std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^
                              static_cast<std::uint32_t>(y) * 19349663u ^ seed * 83492791u;
            h ^= h >> 13;
            h *= 0x5bd1e995u;
            h ^= h >> 15;
            const double noise = static_cast<double>(h % 5) - 2.0;
            const double value = 12.0 + 208.0 * std::pow(level, 2.2) + noise;
            image.samples[static_cast<std::size_t>(y * kWidth + x)] =
                static_cast<std::uint16_t>(std::lround(std::clamp(value, 0.0, 255.0)));
        }
    }
    return image;
}

CameraImage blend(const CameraImage& a, const CameraImage& b) {
    CameraImage out = a;
    for (std::size_t i = 0; i < out.samples.size(); ++i) {
        out.samples[i] = static_cast<std::uint16_t>((a.samples[i] + b.samples[i]) / 2);
    }
    return out;
}

class ScanFrameCheckTest : public ::testing::Test {
protected:
    ScanFrameCheckTest() : sequence_(parameters()), check_(sequence_, {}) {}

    // Passes patterns [from, to) with clean captures.
    void passClean(std::size_t from, std::size_t to) {
        for (std::size_t i = from; i < to; ++i) {
            const FrameVerdict verdict = check_.check(i, captureOf(sequence_, i, 100 + i));
            ASSERT_TRUE(verdict.passed())
                << sequence_.patterns()[i].name() << ": " << verdict.detail;
        }
    }
    std::size_t indexOf(const char* name) const {
        const int index = sequence_.find(name);
        EXPECT_GE(index, 0) << name;
        return static_cast<std::size_t>(index);
    }

    proto::StructuredLightSequence sequence_;
    ScanFrameCheck check_;
};

TEST_F(ScanFrameCheckTest, GroupsWhiteWithBlackAndEachGrayWithItsInverse) {
    const auto& groups = check_.groups();
    ASSERT_FALSE(groups.empty());
    EXPECT_EQ(groups[0], (std::vector<std::size_t>{0, 1}));
    std::size_t covered = 0, pairs = 0, singles = 0;
    for (const auto& group : groups) {
        ASSERT_EQ(group.front(), covered);
        covered += group.size();
        if (group.size() == 2 && sequence_.patterns()[group[0]].kind == proto::PatternKind::kGray) {
            ++pairs;
            EXPECT_TRUE(sequence_.patterns()[group[1]].inverted);
        } else if (group.size() == 1) {
            ++singles;
            EXPECT_EQ(sequence_.patterns()[group[0]].kind, proto::PatternKind::kPhase);
        }
    }
    EXPECT_EQ(covered, sequence_.patterns().size());
    EXPECT_EQ(singles, 8u);  // 4 steps per axis
    EXPECT_EQ(pairs, (sequence_.patterns().size() - 2 - singles) / 2);
}

TEST_F(ScanFrameCheckTest, PassesACleanCapture) {
    passClean(0, sequence_.patterns().size());
    EXPECT_NEAR(check_.litFraction(), static_cast<double>(kLitColumns) / kWidth, 1e-9);
    // Uniform noise of ±2 levels: σ ≈ 1.4.
    EXPECT_GT(check_.noiseSigma(), 0.5);
    EXPECT_LT(check_.noiseSigma(), 3.0);
}

TEST_F(ScanFrameCheckTest, RefusesAStaleWhite) {
    // The projector still showed black when white was captured.
    ASSERT_TRUE(check_.check(0, captureOf(sequence_, 1, 7)).passed());
    const FrameVerdict verdict = check_.check(1, captureOf(sequence_, 1, 8));
    EXPECT_EQ(verdict.problem, FrameProblem::kNotLit);
    EXPECT_NE(verdict.detail.find("on 0.0% of the camera's pixels (needs 0.5%)"), std::string::npos)
        << verdict.detail;
    // Given again, properly: it passes.
    passClean(0, 2);
}

TEST_F(ScanFrameCheckTest, RefusesAStaleInverse) {
    passClean(0, 2);
    const std::size_t pattern = indexOf("gray-x-b3");
    passClean(2, pattern + 1);
    const FrameVerdict verdict = check_.check(pattern + 1, captureOf(sequence_, pattern, 9));
    EXPECT_EQ(verdict.problem, FrameProblem::kPairMismatch);
    EXPECT_NE(verdict.detail.find("pattern + inverse differ from white + black on 100.0%"),
              std::string::npos)
        << verdict.detail;
    passClean(pattern, pattern + 2);
}

TEST_F(ScanFrameCheckTest, RefusesAStalePattern) {
    // gray-x-b3 captured while the inverse of bit 4 was still up: bimodal, but it does not pair
    // with its inverse.
    passClean(0, 2);
    const std::size_t pattern = indexOf("gray-x-b3");
    passClean(2, pattern);
    ASSERT_TRUE(check_.check(pattern, captureOf(sequence_, pattern - 1, 10)).passed());
    const FrameVerdict verdict = check_.check(pattern + 1, captureOf(sequence_, pattern + 1, 11));
    EXPECT_EQ(verdict.problem, FrameProblem::kPairMismatch) << verdict.detail;
}

TEST_F(ScanFrameCheckTest, RefusesACaptureDuringTheSwitch) {
    passClean(0, 2);
    const std::size_t pattern = indexOf("gray-x-b4");
    passClean(2, pattern);
    const CameraImage blended =
        blend(captureOf(sequence_, pattern - 1, 12), captureOf(sequence_, pattern, 13));
    const FrameVerdict verdict = check_.check(pattern, blended);
    EXPECT_EQ(verdict.problem, FrameProblem::kNotBimodal);
    EXPECT_NE(verdict.detail.find("of the lit pixels lie between black and white (at most 20.0%)"),
              std::string::npos)
        << verdict.detail;
}

TEST_F(ScanFrameCheckTest, RefusesARepeatedPhaseStep) {
    const std::size_t step = indexOf("phase-x-s2");
    passClean(0, step);
    const FrameVerdict verdict = check_.check(step, captureOf(sequence_, step - 1, 14));
    EXPECT_EQ(verdict.problem, FrameProblem::kUnchanged);
    EXPECT_NE(verdict.detail.find("of the lit pixels changed since the previous capture"),
              std::string::npos)
        << verdict.detail;
    passClean(step, sequence_.patterns().size());
}

TEST(ScanFrameCheckProblemTest, Names) {
    EXPECT_STREQ(frameProblemName(FrameProblem::kNotLit), "not_lit");
    EXPECT_STREQ(frameProblemName(FrameProblem::kNotBimodal), "not_bimodal");
    EXPECT_STREQ(frameProblemName(FrameProblem::kPairMismatch), "pair_mismatch");
    EXPECT_STREQ(frameProblemName(FrameProblem::kUnchanged), "unchanged");
}

}  // namespace
}  // namespace vpe::firmware
