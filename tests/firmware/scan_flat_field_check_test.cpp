// SPDX-License-Identifier: MIT
// FlatFieldCheck on synthetic colour captures: a camera that sees the projector pixel for pixel
// (a strip at the right in shadow), each channel through a 2.2 gamma above a black level, with
// noise. The capture order puts every flat field far from the one before it; a clean capture of
// every field passes (with and without the bracketed ramp); a stale white and a stale field are
// refused with their problem, and the field given again passes; a grey image is refused.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/firmware/scan/flat_field_check.h"
#include "vpe/proto/radiometry_capture.h"

namespace vpe::firmware {
namespace {

constexpr int kWidth = 64, kHeight = 32;
constexpr int kLitColumns = 56;      // columns 56..63 are in shadow
constexpr double kNoiseSigma = 1.4;  // uniform noise of ±2 levels

std::vector<proto::FlatField> sequenceOf(proto::CameraResponseKind response, int levels = 16) {
    proto::RadiometryParameters p;
    p.width = kWidth;
    p.height = kHeight;
    p.levels = levels;
    p.cameraResponse = response;
    return proto::radiometrySequence(p);
}

// The camera's image of `field`: each channel 12 + 208 × exposure × level^2.2, noise of ±2 from
// a hash of the pixel, the channel and `seed`.
CameraImage captureOf(const proto::FlatField& field, std::uint32_t seed) {
    CameraImage image;
    image.width = kWidth;
    image.height = kHeight;
    image.channels = 3;
    image.maxValue = 255;
    image.samples.resize(image.sampleCount());
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const std::array<std::uint8_t, 3> codes = field.codes(x, kWidth);
            for (int c = 0; c < 3; ++c) {
                const double level =
                    x < kLitColumns ? codes[static_cast<std::size_t>(c)] / 255.0 : 0.0;
                std::uint32_t h = static_cast<std::uint32_t>(x) * 73856093u ^
                                  static_cast<std::uint32_t>(y) * 19349663u ^
                                  static_cast<std::uint32_t>(c) * 2654435761u ^ seed * 83492791u;
                h ^= h >> 13;
                h *= 0x5bd1e995u;
                h ^= h >> 15;
                const double noise = static_cast<double>(h % 5) - 2.0;
                const double value =
                    12.0 + 208.0 * field.exposureScale() * std::pow(level, 2.2) + noise;
                image.samples[3 * static_cast<std::size_t>(y * kWidth + x) +
                              static_cast<std::size_t>(c)] =
                    static_cast<std::uint16_t>(std::lround(std::clamp(value, 0.0, 255.0)));
            }
        }
    }
    return image;
}

// Every group of `check` with clean captures.
void passAll(FlatFieldCheck& check, const std::vector<proto::FlatField>& fields) {
    std::uint32_t seed = 100;
    for (const std::vector<std::size_t>& group : check.groups()) {
        for (const std::size_t index : group) {
            const FrameVerdict verdict = check.check(index, captureOf(fields[index], ++seed));
            ASSERT_TRUE(verdict.passed()) << fields[index].name() << ": " << verdict.detail;
        }
    }
}

TEST(FlatFieldCheckTest, CapturesEveryFieldOnceFarFromTheOneBefore) {
    const std::vector<proto::FlatField> fields = sequenceOf(proto::CameraResponseKind::kUnknown);
    const FlatFieldCheck check(fields, {}, kNoiseSigma);
    const auto& groups = check.groups();
    ASSERT_FALSE(groups.empty());
    EXPECT_EQ(groups[0], (std::vector<std::size_t>{0, 1}));  // black with white
    std::vector<int> seen(fields.size(), 0);
    std::vector<std::size_t> order;
    for (const auto& group : groups) {
        for (const std::size_t index : group) {
            ++seen[index];
            order.push_back(index);
        }
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(fields.size()));
    std::vector<int> ramps;
    for (std::size_t k = 1; k < order.size(); ++k) {
        const proto::FlatField& before = fields[order[k - 1]];
        const proto::FlatField& field = fields[order[k]];
        if (field.kind == proto::FlatFieldKind::kPrimary &&
            before.kind == proto::FlatFieldKind::kPrimary && before.channel == field.channel) {
            // Half the ladder apart, one of the two at 128 or above.
            EXPECT_GE(std::abs(field.code - before.code), 7 * 16 - 1)
                << before.name() << " then " << field.name();
            EXPECT_GE(std::max(field.code, before.code), 128);
        }
        if (field.kind == proto::FlatFieldKind::kRamp) {
            ramps.push_back(field.exposureStop);
        }
    }
    EXPECT_EQ(ramps, (std::vector<int>{0, 4, 1, 3, 2}));
    // The primaries in channel order, the ramps last.
    EXPECT_EQ(fields[order[2]].name(), "flat-red-016");
    EXPECT_EQ(fields[order[3]].name(), "flat-red-143");
    EXPECT_EQ(fields[order[17]].name(), "flat-red-255");
    EXPECT_EQ(fields[order[18]].name(), "flat-green-016");
}

TEST(FlatFieldCheckTest, PassesACleanCapture) {
    for (const auto response :
         {proto::CameraResponseKind::kLinear, proto::CameraResponseKind::kUnknown}) {
        const std::vector<proto::FlatField> fields = sequenceOf(response);
        FlatFieldCheck check(fields, {}, kNoiseSigma);
        passAll(check, fields);
        EXPECT_NEAR(check.litFraction(), static_cast<double>(kLitColumns) / kWidth, 1e-9);
    }
    // The shortest ladder too.
    const std::vector<proto::FlatField> fields = sequenceOf(proto::CameraResponseKind::kLinear, 2);
    FlatFieldCheck check(fields, {}, kNoiseSigma);
    passAll(check, fields);
}

TEST(FlatFieldCheckTest, RefusesAStaleWhite) {
    const std::vector<proto::FlatField> fields = sequenceOf(proto::CameraResponseKind::kLinear);
    FlatFieldCheck check(fields, {}, kNoiseSigma);
    ASSERT_TRUE(check.check(0, captureOf(fields[0], 1)).passed());
    // The projector still showed black when white was captured.
    const FrameVerdict stale = check.check(1, captureOf(fields[0], 2));
    EXPECT_EQ(stale.problem, FrameProblem::kNotLit);
    EXPECT_NE(stale.detail.find("white − black reaches 5.0% of full scale on 0.0%"),
              std::string::npos)
        << stale.detail;
    // Given again, from black.
    ASSERT_TRUE(check.check(0, captureOf(fields[0], 3)).passed());
    EXPECT_TRUE(check.check(1, captureOf(fields[1], 4)).passed());
}

TEST(FlatFieldCheckTest, RefusesAFieldThatRepeatsTheOneBefore) {
    const std::vector<proto::FlatField> fields = sequenceOf(proto::CameraResponseKind::kUnknown);
    FlatFieldCheck check(fields, {}, kNoiseSigma);
    const auto& groups = check.groups();
    std::uint32_t seed = 10;
    // Black, white and the first ladder step, clean.
    for (std::size_t g = 0; g < 2; ++g) {
        for (const std::size_t index : groups[g]) {
            ASSERT_TRUE(check.check(index, captureOf(fields[index], ++seed)).passed());
        }
    }
    const std::size_t previous = groups[1].front(), next = groups[2].front();
    // The next step captured before the projector showed it: the previous one, fresh noise.
    const FrameVerdict stale = check.check(next, captureOf(fields[previous], ++seed));
    EXPECT_EQ(stale.problem, FrameProblem::kUnchanged);
    EXPECT_EQ(stale.detail.rfind("only 0.0% of the lit pixels changed since the previous capture "
                                 "(a flat field after another changes at least 5.0%)",
                                 0),
              0u)
        << stale.detail;
    EXPECT_TRUE(check.check(next, captureOf(fields[next], ++seed)).passed());
    // And a stale ramp: the bracket's exposures alternate, so each differs from the one before.
    for (std::size_t g = 3; g + 1 < groups.size(); ++g) {
        ASSERT_TRUE(
            check.check(groups[g].front(), captureOf(fields[groups[g].front()], ++seed)).passed());
    }
    const std::size_t lastRamp = groups.back().front();
    const std::size_t rampBefore = groups[groups.size() - 2].front();
    EXPECT_EQ(check.check(lastRamp, captureOf(fields[rampBefore], ++seed)).problem,
              FrameProblem::kUnchanged);
    EXPECT_TRUE(check.check(lastRamp, captureOf(fields[lastRamp], ++seed)).passed());
}

TEST(FlatFieldCheckTest, RefusesAGreyImage) {
    const std::vector<proto::FlatField> fields = sequenceOf(proto::CameraResponseKind::kLinear);
    FlatFieldCheck check(fields, {}, kNoiseSigma);
    CameraImage grey;
    grey.width = kWidth;
    grey.height = kHeight;
    grey.samples.resize(grey.pixelCount());
    EXPECT_THROW(check.check(0, grey), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::firmware
