// SPDX-License-Identifier: MIT
// ResponseFunction: gamma and sampled curves, the clamped inverse, and the function of a
// bundle's response curves.
#include "vpe/proto/response_function.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

TEST(ResponseFunction, GammaAndItsInverse) {
    const ResponseFunction response = ResponseFunction::gamma({2.2, 2.0, 2.4});
    for (int c = 0; c < 3; ++c) {
        for (double level = 0; level <= 1.0; level += 0.05) {
            EXPECT_NEAR(response.level(c, response.output(c, level)), level, 1e-12);
        }
        EXPECT_EQ(response.output(c, 1.0), 1.0);
        EXPECT_EQ(response.blackLevel(c), 0.0);
        EXPECT_EQ(response.level(c, 1.7), 1.0);  // clamped
        EXPECT_EQ(response.level(c, -0.2), 0.0);
        EXPECT_EQ(response.level(c, std::nan("")), 0.0);
    }
    EXPECT_NEAR(response.output(0, 0.5), std::pow(0.5, 2.2), 1e-15);
    EXPECT_NEAR(response.output(2, 0.5), std::pow(0.5, 2.4), 1e-15);
    EXPECT_THROW(ResponseFunction::gamma(0.0), std::invalid_argument);
}

TEST(ResponseFunction, SampledCurveIsNormalizedAndInvertedAtItsLowestLevel) {
    // Red: a black level of 0.1 (of 2.0 full) and a flat stretch; green saturates at 0.75.
    const ResponseFunction response = ResponseFunction::sampled(
        {0, 0.25, 0.5, 0.75, 1},
        {{{0.2, 0.5, 0.5, 1.2, 2.0}, {0, 1, 2, 4, 4}, {0, 0.25, 0.5, 0.75, 1}}});
    EXPECT_DOUBLE_EQ(response.blackLevel(0), 0.1);
    EXPECT_DOUBLE_EQ(response.output(0, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(response.output(0, 0.125), 0.175);
    EXPECT_DOUBLE_EQ(response.level(0, 0.25), 0.25);  // the flat stretch: its lowest level
    EXPECT_DOUBLE_EQ(response.level(0, 0.05), 0.0);   // below black
    EXPECT_DOUBLE_EQ(response.level(1, 1.0), 0.75);   // saturated early
    EXPECT_DOUBLE_EQ(response.level(1, 5.0), 0.75);
    for (double level = 0; level <= 1.0; level += 0.01) {
        EXPECT_NEAR(response.level(2, response.output(2, level)), level, 1e-12);
        EXPECT_NEAR(response.output(0, response.level(0, response.output(0, level))),
                    response.output(0, level), 1e-12);
    }
}

TEST(ResponseFunction, ChannelsMayHaveTheirOwnSamples) {
    const ResponseFunction response = ResponseFunction::sampled(
        {{{0, 1}, {0, 0.5, 1}, {0, 0.25, 0.5, 0.75, 1}}}, {{{0, 2}, {0, 1, 4}, {0, 1, 2, 3, 4}}});
    EXPECT_DOUBLE_EQ(response.output(0, 0.5), 0.5);
    EXPECT_DOUBLE_EQ(response.output(1, 0.5), 0.25);
    EXPECT_DOUBLE_EQ(response.output(1, 0.75), 0.625);
    EXPECT_DOUBLE_EQ(response.level(1, 0.625), 0.75);
    EXPECT_DOUBLE_EQ(response.output(2, 0.6), 0.6);
    EXPECT_THROW(
        ResponseFunction::sampled({{{0, 1}, {0, 1}, {0, 1}}}, {{{0, 1}, {0, 1}, {0, 0.5, 1}}}),
        std::invalid_argument);
}

TEST(ResponseFunction, SampledCurveRefusesBadSamples) {
    const std::array<std::vector<double>, 3> rising{{{0, 1}, {0, 1}, {0, 1}}};
    EXPECT_THROW(ResponseFunction::sampled({0}, {{{0}, {0}, {0}}}), std::invalid_argument);
    EXPECT_THROW(ResponseFunction::sampled({0.1, 1}, rising), std::invalid_argument);
    EXPECT_THROW(
        ResponseFunction::sampled({0, 0.5, 0.5, 1}, {{{0, 1, 1, 1}, {0, 1, 1, 1}, {0, 1, 1, 1}}}),
        std::invalid_argument);
    EXPECT_THROW(ResponseFunction::sampled({0, 0.5, 1}, {{{0, 0.6, 0.5}, {0, 1, 2}, {0, 1, 2}}}),
                 std::invalid_argument);
    EXPECT_THROW(ResponseFunction::sampled({0, 1}, {{{1, 1}, {0, 1}, {0, 1}}}),
                 std::invalid_argument);
    EXPECT_THROW(ResponseFunction::sampled({0, 1}, {{{0, 1}, {0, 1}, {0, 1, 2}}}),
                 std::invalid_argument);
}

// A bundle's curves: gammas stay gammas, sample i of N sits at level i / (N − 1), and each
// channel may have its own N.
TEST(ResponseFunction, OfABundlesCurves) {
    ResponseCurves gamma;
    gamma.kind = ResponseKind::kGamma;
    gamma.gamma = {2.2f, 2.0f, 2.4f};
    const ResponseFunction fromGamma = responseFunctionOf(gamma);
    EXPECT_TRUE(fromGamma.isGamma());
    EXPECT_DOUBLE_EQ(fromGamma.output(2, 0.5), std::pow(0.5, static_cast<double>(2.4f)));

    ResponseCurves curve;
    curve.kind = ResponseKind::kCurve;
    curve.curve = {std::vector<float>{0.0f, 2.0f}, std::vector<float>{0.1f, 0.5f, 1.0f},
                   std::vector<float>{0.0f, 1.0f, 2.0f, 3.0f, 4.0f}};
    const ResponseFunction fromCurve = responseFunctionOf(curve);
    EXPECT_FALSE(fromCurve.isGamma());
    EXPECT_DOUBLE_EQ(fromCurve.output(0, 0.25), 0.25);
    EXPECT_NEAR(fromCurve.blackLevel(1), 0.1, 1e-7);
    EXPECT_NEAR(fromCurve.output(1, 0.5), 0.5, 1e-7);
    EXPECT_DOUBLE_EQ(fromCurve.output(2, 0.625), 0.625);
    EXPECT_DOUBLE_EQ(fromCurve.level(2, 0.375), 0.375);

    curve.curve[1] = {0.5f, 0.5f};  // flat: nothing to invert
    EXPECT_THROW(responseFunctionOf(curve), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::proto
