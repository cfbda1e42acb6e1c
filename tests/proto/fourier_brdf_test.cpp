// SPDX-License-Identifier: MIT
// The model's basis and evaluator: recurrences against the direct trigonometric form.
#include "vpe/proto/fourier_brdf.h"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

TEST(FourierBrdfLayout, InterleavedSoSmallerModelsArePrefixes) {
    EXPECT_EQ(coefficientCount(10), 22);
    EXPECT_EQ(kLambertIndex, 0);
    EXPECT_EQ(kConstantIndex, 1);
    EXPECT_EQ(cosineIndex(1), 2);
    EXPECT_EQ(sineIndex(1), 3);
    EXPECT_EQ(cosineIndex(10), 20);
    EXPECT_EQ(sineIndex(10), 21);
    for (int m = 1; m <= kMaxHarmonics; ++m) {
        EXPECT_EQ(harmonicOf(cosineIndex(m)), m);
        EXPECT_EQ(harmonicOf(sineIndex(m)), m);
        EXPECT_LT(sineIndex(m), coefficientCount(m));
    }
}

TEST(FourierBrdfLayout, SmoothnessPenalizesOnlyHarmonicsByMSquared) {
    EXPECT_EQ(smoothnessWeight(kLambertIndex), 0.0);
    EXPECT_EQ(smoothnessWeight(kConstantIndex), 0.0);
    EXPECT_EQ(smoothnessWeight(cosineIndex(3)), 9.0);
    EXPECT_EQ(smoothnessWeight(sineIndex(7)), 49.0);
}

TEST(HarmonicRecurrence, EqualsDirectCosAndSinOverTheWholeRange) {
    for (int i = 0; i <= 1000; ++i) {
        const double theta = M_PI * i / 1000.0;
        HarmonicRecurrence<double> harmonic(std::cos(theta));
        for (int m = 1; m <= kMaxHarmonics; ++m, harmonic.next()) {
            ASSERT_NEAR(harmonic.cosine(), std::cos(m * theta), 1e-12) << "m=" << m;
            ASSERT_NEAR(harmonic.sine(), std::sin(m * theta), 1e-12) << "m=" << m;
        }
    }
}

TEST(HarmonicRecurrence, FloatStaysWithinRoundingOfDouble) {
    for (int i = 0; i <= 200; ++i) {
        const double theta = M_PI * i / 200.0;
        HarmonicRecurrence<float> harmonic(static_cast<float>(std::cos(theta)));
        for (int m = 1; m <= 20; ++m, harmonic.next()) {
            // Forward Chebyshev recurrences lose up to a few m² ulps near the ends of [-1, 1]
            // (float ulp 6e-8, m² = 400).
            ASSERT_NEAR(harmonic.cosine(), std::cos(m * theta), 5e-5) << "m=" << m;
            ASSERT_NEAR(harmonic.sine(), std::sin(m * theta), 5e-5) << "m=" << m;
        }
    }
}

TEST(FourierBrdf, EvaluatorEqualsDirectForm) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int trial = 0; trial < 500; ++trial) {
        const int harmonics = trial % (kMaxHarmonics + 1);
        std::vector<double> c(static_cast<std::size_t>(coefficientCount(harmonics)));
        for (double& v : c) {
            v = uniform(random);
        }
        const double thetaD = std::acos(uniform(random));
        const double thetaS = M_PI * (uniform(random) + 1.0) / 2.0;
        const double fast =
            evaluateFourierBrdf(c.data(), harmonics, std::cos(thetaD), std::cos(thetaS));
        const double direct = evaluateFourierBrdfDirect(c.data(), harmonics, thetaD, thetaS);
        ASSERT_NEAR(fast, direct, 1e-11) << "M=" << harmonics;
    }
}

TEST(FourierBrdf, EvaluatorIsTheBasisDottedWithTheCoefficients) {
    const int harmonics = 10;
    std::vector<double> c(coefficientCount(harmonics));
    for (std::size_t i = 0; i < c.size(); ++i) {
        c[i] = std::sin(1.0 + static_cast<double>(i));
    }
    std::vector<double> basis(c.size());
    for (double cd : {-0.3, 0.0, 0.4, 1.0}) {
        for (double cs : {-1.0, -0.2, 0.5, 1.0}) {
            fourierBasis(cd, cs, harmonics, basis.data());
            double dot = 0;
            for (std::size_t i = 0; i < c.size(); ++i) {
                dot += c[i] * basis[i];
            }
            EXPECT_NEAR(evaluateFourierBrdf(c.data(), harmonics, cd, cs), dot, 1e-13);
        }
    }
}

// The three-channel form shares the recurrence and must give each channel's value exactly,
// bit for bit: the extended fit compares training errors of near-equal tilts with it.
TEST(FourierBrdf, RgbEvaluatorEqualsEachChannelExactly) {
    constexpr int kStride = 32;
    std::mt19937 random(7);
    std::uniform_real_distribution<float> coefficient(-1.0f, 1.0f);
    std::uniform_real_distribution<double> cosine(-1.2, 1.2);
    for (int harmonics : {0, 1, 6, 10, 15}) {
        float c[3][kStride];
        for (auto& channel : c) {
            for (float& value : channel) {
                value = coefficient(random);
            }
        }
        for (int trial = 0; trial < 50; ++trial) {
            const double cd = cosine(random), cs = cosine(random);
            double rgb[3];
            evaluateFourierBrdfRgb(&c[0][0], kStride, harmonics, cd, cs, rgb);
            for (int k = 0; k < 3; ++k) {
                EXPECT_EQ(rgb[k], evaluateFourierBrdf(c[k], harmonics, cd, cs))
                    << "M = " << harmonics << ", channel " << k;
            }
        }
    }
}

TEST(FourierBrdf, LambertTermIsClampedBelowTheHorizon) {
    std::vector<double> c(coefficientCount(0), 0.0);
    c[kLambertIndex] = 2.0;
    EXPECT_DOUBLE_EQ(evaluateFourierBrdf(c.data(), 0, 0.5, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(evaluateFourierBrdf(c.data(), 0, -0.5, 1.0), 0.0);
    c[kConstantIndex] = std::sqrt(2.0);
    EXPECT_NEAR(evaluateFourierBrdf(c.data(), 0, -0.5, 1.0), 1.0, 1e-15);
}

TEST(FourierBrdf, OutOfRangeCosineIsClampedNotNaN) {
    std::vector<double> c(coefficientCount(4), 0.1);
    EXPECT_TRUE(std::isfinite(evaluateFourierBrdf(c.data(), 4, 0.5, 1.0000001)));
    EXPECT_TRUE(std::isfinite(evaluateFourierBrdf(c.data(), 4, 0.5, -1.0000001)));
}

}  // namespace
}  // namespace vpe::proto
