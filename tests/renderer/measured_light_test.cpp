// SPDX-License-Identifier: MIT
// The compensation from measured light: the inverse of C = D + F · X · g(level) where the
// projector can give the target, a smooth roll-off where it cannot, and a gain limit that
// keeps a pixel below the knee.
#include "vpe/renderer/cpu/measured_light.h"

#include <cmath>

#include <gtest/gtest.h>

namespace vpe::renderer {
namespace {

const std::array<double, 9> kMixing{1, 0.076, 0.011, 0.068, 1, 0.057, 0.011, 0.097, 1};

proto::ResponseFunction aboveBlack() {
    std::vector<double> levels;
    std::array<std::vector<double>, 3> outputs;
    for (int i = 0; i <= 32; ++i) {
        const double v = i / 32.0;
        levels.push_back(v);
        outputs[0].push_back(std::pow(v, 2.4));
        outputs[1].push_back(0.8 * std::pow(v, 2.2) + 0.2 * v * v * (3 - 2 * v));
        outputs[2].push_back(std::pow(v, 2.7));
    }
    return proto::ResponseFunction::sampled(levels, outputs);
}

// The forward model at one pixel.
std::array<double, 3> seen(const float* f, const float* d, const proto::ResponseFunction& g,
                           const std::array<double, 3>& level) {
    std::array<double, 3> c{};
    for (std::size_t k = 0; k < 3; ++k) {
        double mixed = 0;
        for (std::size_t j = 0; j < 3; ++j) {
            mixed += kMixing[3 * k + j] * g.output(static_cast<int>(j), level[j]);
        }
        c[k] = double(d[k]) + double(f[k]) * mixed;
    }
    return c;
}

TEST(MeasuredLight, InvertsTheMeasuredModelWhereTheProjectorCanGiveTheTarget) {
    const proto::ResponseFunction g = aboveBlack();
    const proto::InverseResponseTable table(g);
    const std::array<double, 9> inverse = inverse3x3(kMixing);
    const float f[3] = {0.31f, 0.27f, 0.22f}, d[3] = {0.012f, 0.011f, 0.009f};
    int checked = 0;
    for (double r = 0.05; r < 0.25; r += 0.04) {
        for (double b = 0.03; b < 0.18; b += 0.05) {
            const std::array<double, 3> target{r, 0.6 * r + 0.3 * b, b};
            const CompensatedPixel pixel =
                compensateMeasuredPixel(f, d, inverse, table, target, 1.0);
            if (pixel.clippedHigh || pixel.clippedLow) {
                continue;
            }
            const std::array<double, 3> c = seen(f, d, g, pixel.level);
            for (std::size_t k = 0; k < 3; ++k) {
                // Through the device's table (half-float levels: 2⁻¹¹ of a level, × γ ≈ 2.4 in
                // output): measured within 0.06 % of the target, a twentieth of an 8-bit level.
                EXPECT_NEAR(c[k], target[k], 1.5e-3 * target[k] + 1e-5)
                    << r << " " << b << " " << k;
            }
            ++checked;
        }
    }
    EXPECT_GT(checked, 10);
}

TEST(MeasuredLight, RollsOffAboveTheKneeWithoutAStep) {
    std::array<double, 3> previous{};
    double last = 0.5;
    for (double t = 0.5; t < 3; t += 0.001) {
        std::array<double, 3> w{t, 0.5 * t, 0.25 * t};
        const bool rolled = rollOffHighlight(w);
        EXPECT_EQ(rolled, t > kHighlightKnee);
        EXPECT_LE(w[0], 1.0);
        EXPECT_GE(w[0], last - 1e-12);         // monotone
        EXPECT_LT(w[0] - last, 0.0011);        // continuous, slope ≤ 1
        EXPECT_NEAR(w[1] / w[0], 0.5, 1e-12);  // the hue kept
        EXPECT_NEAR(w[2] / w[0], 0.25, 1e-12);
        last = w[0];
        previous = w;
    }
    EXPECT_GT(previous[0], 0.999);
}

TEST(MeasuredLight, TheGainLimitIsWhereThePixelReachesTheKnee) {
    const proto::ResponseFunction g = aboveBlack();
    const proto::InverseResponseTable table(g);
    const std::array<double, 9> inverse = inverse3x3(kMixing);
    const float f[3] = {0.31f, 0.27f, 0.22f}, d[3] = {0.012f, 0.011f, 0.009f};
    const std::array<double, 3> target{0.2, 0.15, 0.1};
    const CompensatedPixel pixel = compensateMeasuredPixel(f, d, inverse, table, target, 1.0);
    const double limit = pixel.gainLimit;
    ASSERT_TRUE(std::isfinite(limit));
    const auto at = [&](double gain) {
        std::array<double, 3> scaled{};
        for (std::size_t k = 0; k < 3; ++k) {
            scaled[k] = target[k] * gain;
        }
        return compensateMeasuredPixel(f, d, inverse, table, scaled, gain);
    };
    EXPECT_FALSE(at(0.999 * limit).clippedHigh);
    EXPECT_TRUE(at(1.001 * limit).clippedHigh);
    EXPECT_NEAR(at(2.0).gainLimit, limit, 1e-9 * limit);  // a property of the pixel
}

TEST(MeasuredLight, BelowTheFloorIsBlackAndNoLightMeasuredIsClipped) {
    const proto::ResponseFunction g = aboveBlack();
    const proto::InverseResponseTable table(g);
    const std::array<double, 9> inverse = inverse3x3(kMixing);
    const float f[3] = {0.3f, 0.3f, 0.3f}, d[3] = {0.05f, 0.05f, 0.05f};
    const CompensatedPixel dark =
        compensateMeasuredPixel(f, d, inverse, table, {0.01, 0.01, 0.01}, 1);
    EXPECT_TRUE(dark.clippedLow);
    EXPECT_EQ(dark.level, (std::array<double, 3>{0, 0, 0}));
    const float none[3] = {0, 0, 0};
    const CompensatedPixel unlit =
        compensateMeasuredPixel(none, d, inverse, table, {0.2, 0.2, 0.2}, 1);
    EXPECT_TRUE(unlit.clippedHigh);
    EXPECT_THROW(inverse3x3({1, 1, 1, 1, 1, 1, 1, 1, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace vpe::renderer
