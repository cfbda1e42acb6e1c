// SPDX-License-Identifier: MIT
// `vpe relight`: a calibrated model's picture under one of its capture's lights is what the
// model predicts the capture's camera saw (vpe eval's eval::CapturePredictor); --as material is
// the material alone, and each says which it is.
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "vpe/capture/transfer_function.h"
#include "vpe/eval/capture_predictor.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/model/light_transport.h"
#include "vpe/proto/fourier_brdf.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::CommandResult;
using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

constexpr int kWidth = 24;
constexpr int kHeight = 16;
constexpr int kHarmonics = 2;

// An extended model fitted under a calibrated rig: perspective camera, lights at a finite
// distance, a near-linear camera response, and a light transport that shades the texels
// unevenly, as on item1 (where the picture from +z under a directional light, sRGB, was
// 10–12 dB from the model's own predictions).
model::ModelInfo calibratedInfo() {
    model::ModelInfo info = model::fourierModelInfo(kWidth, kHeight, kHarmonics, 0.5, 48);
    info.variant = "extended";
    info.capture = "/captures/door/dirs.lp";
    info.calibration.fieldOfViewDegrees = 30;
    info.calibration.lightDistance = 4;
    info.calibration.responseGamma = 1.2;
    return info;
}

model::ModelRows calibratedRows() {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    model::ModelRows rows;
    rows.resize(kWidth, kHeight, proto::coefficientCount(kHarmonics), true);
    for (std::size_t p = 0; p < rows.valid.size(); ++p) {
        rows.valid[p] = p % 7 != 3 ? 1 : 0;
        const double nx = 0.3 * (unit(random) - 0.5);
        const double ny = 0.3 * (unit(random) - 0.5);
        const double nz = std::sqrt(1.0 - nx * nx - ny * ny);
        rows.normal[p * 3] = static_cast<float>(nx);
        rows.normal[p * 3 + 1] = static_cast<float>(ny);
        rows.normal[p * 3 + 2] = static_cast<float>(nz);
        for (int c = 0; c < 3; ++c) {
            float* k = rows.coefficient.data() + (p * 3 + static_cast<std::size_t>(c)) *
                                                     static_cast<std::size_t>(rows.coefficients);
            k[0] = 0.25f + 0.3f * unit(random);  // kd
            for (int i = 1; i < rows.coefficients; ++i) {
                k[i] = 0.05f * unit(random);
            }
        }
        double identity[model::kTransportTerms];
        model::identityTransport(identity);
        for (int c = 0; c < model::kTransportChannels; ++c) {
            for (int t = 0; t < model::kTransportTerms; ++t) {
                // T ≡ 0.6–1 of the identity's level, with a little variation over the dome.
                const double value =
                    t == 0 ? identity[0] * (0.6 + 0.4 * unit(random)) : 0.05 * (unit(random) - 0.5);
                rows.transport[p * model::kTransportValues +
                               static_cast<std::size_t>(c) * model::kTransportTerms +
                               static_cast<std::size_t>(t)] = static_cast<float>(value);
            }
        }
    }
    return rows;
}

class RelightCommand : public ::testing::Test {
protected:
    void SetUp() override {
        model::ModelWriter writer(folder_ / "model.exr", calibratedInfo());
        writer.writeRows(0, calibratedRows());
        writer.finish();
    }
    std::string path(const char* name) const { return (folder_ / name).string(); }
    testing::TemporaryFolder folder_;
};

// What vpe eval predicts the capture's camera sees under `towardsLight`, as 8-bit codes.
std::vector<float> predictedUnder(const proto::Vec3d& towardsLight) {
    const model::ModelInfo info = calibratedInfo();
    const model::ModelRows rows = calibratedRows();
    capture::Capture capture;  // a light file's capture: what the calibration replaces
    capture::CaptureImage image;
    image.light = towardsLight;
    capture.images = {image};
    const eval::CapturePredictor predictor(info, capture, storedTransfer(capture, true));
    std::vector<float> codes(static_cast<std::size_t>(kWidth) * kHeight * 3, 0.0f);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const std::size_t p = rows.pixel(y, x);
            if (!rows.valid[p]) {
                continue;
            }
            const std::array<double, 3> rgb = predictor.predict(rows, y, x, y, 0);
            for (std::size_t c = 0; c < 3; ++c) {
                codes[p * 3 + c] = static_cast<float>(255.0 * rgb[c]);
            }
        }
    }
    return codes;
}

TEST_F(RelightCommand, UnderACaptureLightShowsTheModelsPrediction) {
    const proto::Vec3d light{0.48, -0.36, 0.8};  // unit, as a light file's direction is read
    const CommandResult result =
        runCommand(vpe({"relight", path("model.exr"), "--out", path("captured.png"), "--light",
                        "0.48,-0.36,0.8"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    EXPECT_NE(result.err.find("as the capture's camera recorded it"), std::string::npos)
        << result.err;
    EXPECT_NE(result.err.find("30° perspective"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("light transport T"), std::string::npos) << result.err;
    const image::FloatImage picture = image::readImage(path("captured.png"));
    ASSERT_EQ(picture.width, kWidth);
    ASSERT_EQ(picture.height, kHeight);
    const std::vector<float> predicted = predictedUnder(light);
    double worst = 0;
    double level = 0;
    for (std::size_t i = 0; i < predicted.size(); ++i) {
        const double code =
            255.0 * picture.pixels[i / 3 * static_cast<std::size_t>(picture.channels) + i % 3];
        worst = std::max(worst, std::fabs(code - predicted[i]));
        level += predicted[i] / static_cast<double>(predicted.size());
    }
    // Only the PNG's rounding between them.
    EXPECT_LE(worst, 0.5 + 1e-3);
    EXPECT_GT(level, 20.0);  // not a black picture that would match anything
}

TEST_F(RelightCommand, MaterialAloneIsAnotherPictureAndSaysSo) {
    const CommandResult captured =
        runCommand(vpe({"relight", path("model.exr"), "--out", path("captured.png"), "--light",
                        "0.48,-0.36,0.8"}));
    const CommandResult material =
        runCommand(vpe({"relight", path("model.exr"), "--out", path("material.png"), "--light",
                        "0.48,-0.36,0.8", "--as", "material"}));
    ASSERT_EQ(captured.exitStatus, 0) << captured.err;
    ASSERT_EQ(material.exitStatus, 0) << material.err;
    EXPECT_NE(material.err.find("the material alone"), std::string::npos) << material.err;
    const image::FloatImage a = image::readImage(path("captured.png"));
    const image::FloatImage b = image::readImage(path("material.png"));
    double squared = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        squared += (a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
    }
    const double psnr = 10.0 * std::log10(static_cast<double>(a.pixels.size()) / squared);
    std::printf("[ measure  ] calibrated model: material alone vs as captured %.2f dB\n", psnr);
    EXPECT_LT(psnr, 30.0);
}

TEST_F(RelightCommand, RefusesWhatItCannotRender) {
    testing::expectInputError(
        runCommand(vpe({"relight", path("model.exr"), "--out", path("x.png"), "--light", "0,0,0"})),
        {"--light"});
    testing::expectInputError(
        runCommand(vpe({"relight", path("model.exr"), "--out", path("x.png"), "--exposure", "-1"})),
        {"--exposure"});
}

}  // namespace
}  // namespace vpe
