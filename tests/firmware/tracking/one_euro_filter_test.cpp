// SPDX-License-Identifier: MIT
// OneEuroFilter against values worked out by hand from the paper's equations, and its defining
// properties: a constant passes unchanged, jitter at rest is attenuated, and with β > 0 the lag
// in motion is small.
#include "vpe/firmware/tracking/one_euro_filter.h"

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace vpe::firmware {
namespace {

TEST(OneEuroFilterTest, SmoothingFactorIsTheFirstOrderLowPass) {
    // α = 1 / (1 + τ/Te) = 2π fc Te / (1 + 2π fc Te): fc = 1 Hz, Te = 0.1 s → 0.6283/1.6283.
    EXPECT_NEAR(OneEuroFilter::smoothingFactor(0.1, 1.0), 0.385869545095, 1e-12);
    EXPECT_NEAR(OneEuroFilter::smoothingFactor(1.0 / 30.0, 5.0),
                (2 * std::numbers::pi * 5.0 / 30.0) / (1 + 2 * std::numbers::pi * 5.0 / 30.0),
                1e-15);
}

TEST(OneEuroFilterTest, MatchesHandComputedValues) {
    // β = 0: a plain low-pass at min_cutoff. 0 → 1 over 0.1 s: x̂ = α·1 = 0.385869545095.
    OneEuroFilter plain(OneEuroParameters{1.0, 0.0, 1.0});
    EXPECT_EQ(plain.filter(0.0, 0.0), 0.0);
    EXPECT_NEAR(plain.filter(1.0, 0.1), 0.385869545095, 1e-12);

    // β = 0.5, variable rate.
    OneEuroFilter adaptive(OneEuroParameters{1.0, 0.5, 1.0});
    EXPECT_EQ(adaptive.filter(0.0, 0.0), 0.0);  // the first sample passes through
    // t = 0.1, x = 1: dx = (1 − 0)/0.1 = 10; αd = 0.385869545095; dx̂ = 3.85869545095;
    // fc = 1 + 0.5 · 3.85869545095 = 2.929347725475; α = 1/(1 + 1/(2π·2.929347725475·0.1))
    // = 0.647957169592; x̂ = 0.647957169592.
    EXPECT_NEAR(adaptive.filter(1.0, 0.1), 0.647957169592, 1e-11);
    // t = 0.3 (Te = 0.2), x = 1.5: dx = (1.5 − 0.647957169592)/0.2 = 4.26021415204;
    // αd = 0.556862724144; dx̂ = 0.556862724144·4.26021415204 + 0.443137275856·3.85869545095
    // = 4.082286248633; fc = 3.041143124317; α = 0.792600532852;
    // x̂ = 0.792600532852·1.5 + 0.207399467148·0.647957169592 = 1.323286770986.
    EXPECT_NEAR(adaptive.filter(1.5, 0.3), 1.323286770986, 1e-11);
}

TEST(OneEuroFilterTest, ConstantSignalIsUnchanged) {
    OneEuroFilter filter(OneEuroParameters{0.5, 0.3, 1.0});
    double t = 10.0;
    for (int i = 0; i < 200; ++i) {
        t += 0.005 + 0.03 * (i % 4);  // irregular frame times
        EXPECT_EQ(filter.filter(123.25, t), 123.25);
    }
}

TEST(OneEuroFilterTest, JitterAtRestIsAttenuated) {
    std::mt19937 random(7);
    std::normal_distribution<double> jitter(0.0, 0.3);  // px: centroid noise of a still lamp
    OneEuroFilter filter(OneEuroParameters{1.0, 0.05, 1.0});
    double inputVariance = 0.0;
    double outputVariance = 0.0;
    const int frames = 600;
    for (int i = 0; i < frames; ++i) {
        const double input = 100.0 + jitter(random);
        const double output = filter.filter(input, i / 30.0);
        if (i >= 60) {  // after the start-up transient
            inputVariance += (input - 100.0) * (input - 100.0);
            outputVariance += (output - 100.0) * (output - 100.0);
        }
    }
    const double ratio = std::sqrt(outputVariance / inputVariance);
    // A 1 Hz low-pass at 30 Hz passes about √(α/(2−α)) ≈ 0.33 of white noise's RMS.
    EXPECT_LT(ratio, 0.45);
    EXPECT_GT(ratio, 0.1);  // and it is a low-pass, not a freeze
}

double steadyLag(double beta) {
    OneEuroFilter filter(OneEuroParameters{1.0, beta, 1.0});
    const double speed = 300.0;  // px/s: the lamp swept across the room in a second
    double lag = 0.0;
    for (int i = 0; i <= 90; ++i) {
        const double t = i / 30.0;
        lag = speed * t - filter.filter(speed * t, t);
    }
    return lag;
}

TEST(OneEuroFilterTest, BetaCutsTheLagInMotion) {
    const double withoutBeta = steadyLag(0.0);
    const double withBeta = steadyLag(0.05);
    // Without β: a 1 Hz low-pass lags a ramp by about v·(1−α)/(α·rate) ≈ 300/6.3 px.
    EXPECT_GT(withoutBeta, 35.0);
    // With β = 0.05: fc ≈ 1 + 0.05 · 300 = 16 Hz, lag ≈ 300 · (1−α)/(α·30) ≈ 3 px.
    EXPECT_LT(withBeta, 5.0);
    EXPECT_GT(withBeta, 0.0);
}

TEST(OneEuroFilterTest, StaleTimestampsAndResets) {
    OneEuroFilter filter;
    filter.filter(0.0, 1.0);
    const double moved = filter.filter(10.0, 1.1);
    EXPECT_EQ(filter.filter(50.0, 1.1), moved);   // same time: no step to filter over
    EXPECT_EQ(filter.filter(50.0, 1.05), moved);  // earlier: the same
    filter.reset();
    EXPECT_FALSE(filter.primed());
    EXPECT_EQ(filter.filter(50.0, 0.5), 50.0);  // passes through after a reset
    EXPECT_THROW(filter.filter(NAN, 2.0), std::invalid_argument);
}

TEST(OneEuroFilterTest, RefusesInvalidParameters) {
    EXPECT_THROW(OneEuroFilter(OneEuroParameters{0.0, 0.0, 1.0}), std::invalid_argument);
    EXPECT_THROW(OneEuroFilter(OneEuroParameters{1.0, -0.1, 1.0}), std::invalid_argument);
    EXPECT_THROW(OneEuroFilter(OneEuroParameters{1.0, 0.0, 0.0}), std::invalid_argument);
    EXPECT_THROW(OneEuroFilter(OneEuroParameters{INFINITY, 0.0, 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::firmware
