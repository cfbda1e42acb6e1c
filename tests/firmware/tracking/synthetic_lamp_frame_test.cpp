// SPDX-License-Identifier: MIT
// SyntheticLampFrame: seeded and reproducible, the noise it claims, the spot where it is put,
// and one-line refusals of bad descriptions (replay files are input).
#include "vpe/firmware/tracking/synthetic_lamp_frame.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "../../support/thrown_message.h"

namespace vpe::firmware {
namespace {

std::string errorOf(const SyntheticLampFrame& scene) {
    return vpe::testing::thrownMessage<std::invalid_argument>([&] { scene.render(); });
}

TEST(SyntheticLampFrameTest, IsAPureFunctionOfItsSeed) {
    SyntheticLampFrame scene;
    scene.lamp = SyntheticSpot{100.0, 100.0, 3.0, 255.0};
    const LuminanceFrame a = scene.render();
    const LuminanceFrame b = scene.render();
    EXPECT_EQ(a.pixels, b.pixels);
    scene.seed = 2;
    EXPECT_NE(scene.render().pixels, a.pixels);
    EXPECT_EQ(a.width, 320);
    EXPECT_EQ(a.height, 240);
    EXPECT_EQ(a.pixels.size(), 320u * 240u);
}

TEST(SyntheticLampFrameTest, BackgroundHasTheRequestedNoise) {
    SyntheticLampFrame scene;
    scene.background = 40.0;
    scene.noiseSigma = 5.0;
    const LuminanceFrame frame = scene.render();
    double sum = 0.0;
    double squares = 0.0;
    for (const std::uint8_t p : frame.pixels) {
        sum += p;
        squares += static_cast<double>(p) * p;
    }
    const double n = static_cast<double>(frame.pixels.size());
    const double mean = sum / n;
    // Rounding to integers adds 1/12 to the variance.
    const double sigma = std::sqrt(squares / n - mean * mean - 1.0 / 12.0);
    EXPECT_NEAR(mean, 40.0, 0.1);
    EXPECT_NEAR(sigma, 5.0, 0.1);
}

TEST(SyntheticLampFrameTest, SpotIsWhereItIsPut) {
    SyntheticLampFrame scene;
    scene.noiseSigma = 0.0;
    scene.background = 10.0;
    scene.lamp = SyntheticSpot{50.0, 30.0, 2.0, 200.0};
    const LuminanceFrame frame = scene.render();
    const auto at = [&frame](int x, int y) { return frame.pixels[y * frame.width + x]; };
    EXPECT_EQ(at(50, 30), 210);  // background + peak
    EXPECT_EQ(at(52, 30), static_cast<int>(std::lround(10.0 + 200.0 * std::exp(-0.5))));  // 1 σ
    EXPECT_EQ(at(50, 28), at(52, 30));
    EXPECT_EQ(at(0, 0), 10);
    scene.lamp->peak = 1000.0;
    EXPECT_EQ(scene.render().pixels[30 * 320 + 50], 255);  // saturates
}

TEST(SyntheticLampFrameTest, RefusesBadDescriptionsWithOneLine) {
    SyntheticLampFrame scene;
    scene.width = 0;
    EXPECT_EQ(errorOf(scene),
              "synthetic lamp frame: size must be within 1…4096 × 1…4096, got 0x240");
    scene = SyntheticLampFrame{};
    scene.lamp = SyntheticSpot{10.0, 10.0, -1.0, 255.0};
    EXPECT_EQ(errorOf(scene), "synthetic lamp frame: lamp.radius must be in (0, 4096], got -1");
    scene.lamp = SyntheticSpot{NAN, 10.0, 3.0, 255.0};
    EXPECT_EQ(errorOf(scene), "synthetic lamp frame: lamp has a non-finite position");
    scene.lamp.reset();
    scene.distractors = {{10.0, 10.0, 2.0, 1e9}};
    EXPECT_EQ(errorOf(scene),
              "synthetic lamp frame: distractors[0].peak must be within ±1e6, got 1e+09");
    scene.distractors.clear();
    scene.noiseSigma = -1.0;
    EXPECT_EQ(errorOf(scene), "synthetic lamp frame: noise must be in [0, 1e6], got -1");
}

}  // namespace
}  // namespace vpe::firmware
