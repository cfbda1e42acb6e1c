// SPDX-License-Identifier: MIT
// Transfer fidelity (`vpe transfer`, docs/transfer-fidelity.md) at a small size: a 64² synthetic
// capture with camera noise, fitted by the extended model (the report's default configuration)
// and baked with and without its relief, scored against the true material on the vase under
// the eight views. Thresholds sit just under the values measured; the relief must be worth
// many dB and the SSIM's structure. And the metrics themselves on pictures with known answers.
#include <cmath>
#include <iostream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/image/image_metrics.h"

#include "support/command_runner.h"
#include "support/fitted_capture.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

nlohmann::json lastJson(const std::string& out) {
    const std::size_t start = out.rfind('{', out.rfind("\"views\""));
    return nlohmann::json::parse(out.substr(start));
}

TEST(TransferFidelity, TheReliefCarriedAsADetailMapTransfersTheMaterial) {
    const testing::TemporaryFolder folder;
    const std::string capture = (folder / "capture").string();
    const std::string model = (folder / "extended.exr").string();
    ASSERT_EQ(runCommand(vpe({"synth", "--out", capture, "--size", "64", "--noise", "camera"}))
                  .exitStatus,
              0);
    const testing::CommandResult fitted = runCommand(
        vpe({"fit", capture + "/train", "--out", model, "--model", "extended", "--no-preview"}));
    ASSERT_EQ(fitted.exitStatus, 0) << fitted.err;
    nlohmann::json reports[2];
    for (const bool relief : {true, false}) {
        const std::string bundle = (folder / (relief ? "relief.vpeb" : "flat.vpeb")).string();
        const testing::CommandResult baked = runCommand(
            vpe({"bake", "--texture", model, "--relief", relief ? "on" : "off", "--out", bundle}));
        ASSERT_EQ(baked.exitStatus, 0) << baked.err;
        const testing::CommandResult scored =
            runCommand(vpe({"transfer", capture, bundle, "--json"}));
        ASSERT_EQ(scored.exitStatus, 0) << scored.err;
        std::cout << scored.err;
        reports[relief ? 0 : 1] = lastJson(scored.out);
    }
    const nlohmann::json& relief = reports[0];
    const nlohmann::json& flat = reports[1];
    ASSERT_EQ(relief["views"].size(), 8u);
    EXPECT_TRUE(relief["relief"].get<bool>());
    EXPECT_FALSE(flat["relief"].get<bool>());
    // Measured: 36.03 dB, SSIM 0.9760, relief 0.44° off the truth's; without the relief
    // 23.83 dB, SSIM 0.7816.
    EXPECT_GE(relief["psnr"].get<double>(), 35.5);
    EXPECT_GE(relief["ssim"].get<double>(), 0.972);
    EXPECT_LE(relief["relief_error_degrees"].get<double>(), 0.5);
    EXPECT_GE(relief["psnr"].get<double>() - flat["psnr"].get<double>(), 11.5);
    EXPECT_GE(relief["ssim"].get<double>() - flat["ssim"].get<double>(), 0.18);
}

// The bundle bakes the small fit that every refusal shares (16 × 16), the capture is 8 × 8.
TEST(TransferFidelity, RefusesABundleOfAnotherTextureSize) {
    const testing::TemporaryFolder folder;
    const std::string capture = (folder / "capture").string();
    const std::string model = (testing::smallFittedCapture() / "model.exr").string();
    const std::string bundle = (folder / "scene.vpeb").string();
    ASSERT_EQ(
        runCommand(vpe({"synth", "--out", capture, "--size", "8", "--rig", "dome"})).exitStatus, 0);
    ASSERT_EQ(runCommand(vpe({"bake", "--texture", model, "--out", bundle})).exitStatus, 0);
    const testing::CommandResult refused = runCommand(vpe({"transfer", capture, bundle}));
    EXPECT_EQ(refused.exitStatus, 2);
    EXPECT_NE(refused.err.find("textures of 16 x 16, the capture's truth is 8 x 8"),
              std::string::npos)
        << refused.err;
}

image::Rgb8Image uniform(int width, int height, std::uint8_t value) {
    return {width, height,
            std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3, value)};
}

TEST(ImageMetrics, PsnrAndSsimOfKnownPictures) {
    const image::Rgb8Image a = uniform(20, 16, 100), b = uniform(20, 16, 110);
    const std::vector<std::uint8_t> all(20 * 16, 1);
    EXPECT_NEAR(image::psnr(a, b, all), 10 * std::log10(255.0 * 255.0 / 100.0), 1e-12);
    EXPECT_TRUE(std::isinf(image::psnr(a, a, all)));
    EXPECT_DOUBLE_EQ(image::meanSsim(a, a, all), 1.0);
    // Flat pictures: only the luminance term, (2·μa·μb + C1)/(μa² + μb² + C1).
    const double c1 = (0.01 * 255) * (0.01 * 255);
    EXPECT_NEAR(image::meanSsim(a, b, all),
                (2 * 100.0 * 110 + c1) / (100.0 * 100 + 110.0 * 110 + c1), 1e-12);
    // The map is defined where the 11 × 11 window fits: 10 × 6 pixels here.
    const std::vector<double> map = image::ssimMap(a, b, 0);
    std::size_t defined = 0;
    for (double v : map) {
        defined += std::isnan(v) ? 0 : 1;
    }
    EXPECT_EQ(defined, 10u * 6u);
    // Only masked pixels count; an empty mask gives NaN.
    image::Rgb8Image c = a;
    c.values[3 * (8 * 20 + 10)] = 0;  // one pixel of one channel, inside the valid map
    std::vector<std::uint8_t> one(20 * 16, 0);
    one[8 * 20 + 10] = 1;
    EXPECT_NEAR(image::psnr(a, c, one), 10 * std::log10(255.0 * 255.0 / (100.0 * 100.0 / 3)),
                1e-12);
    EXPECT_LT(image::meanSsim(a, c, one), 1.0);
    EXPECT_TRUE(std::isnan(image::psnr(a, b, std::vector<std::uint8_t>(20 * 16, 0))));
}

TEST(ImageMetrics, SrgbPicturesAreWhatPeopleSee) {
    const image::Rgb8Image picture =
        image::toSrgb8({0.0f, 0.5f, 1.0f, 2.0f, -1.0f, 0.25f}, 2, 1, 2.0);
    EXPECT_EQ(picture.values[0], 0);
    EXPECT_EQ(picture.values[1], 255);  // 0.5 × 2
    EXPECT_EQ(picture.values[3], 255);  // clipped
    EXPECT_EQ(picture.values[4], 0);
    EXPECT_EQ(picture.values[5], 188);  // sRGB(0.5) = 0.7354
}

}  // namespace
}  // namespace vpe
