// SPDX-License-Identifier: MIT
// The classic RTI bases in `vpe fit --model ptm6|hsh16` and `vpe eval`: a capture made from a
// known PTM or HSH is recovered, the held-out protocol scores it, bad names are refused, and
// on a real capture the figures of the RTI literature's protocol come back.
#include "vpe/model/rti_basis.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/model/fourier_model_file.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/synthetic_capture.h"
#include "support/test_data.h"
#include "support/vpe_command_names.h"

namespace vpe {
namespace {

using testing::CommandResult;
using namespace testing::vpe_command_names;  // NOLINT: support/vpe_command_names.h

TEST(RtiBasis, ParsesTheModelNames) {
    const std::vector<std::pair<std::string, std::string>> valid{
        {"ptm", "ptm6"},  {"ptm6", "ptm6"}, {"ptm10", "ptm10"}, {"hsh", "hsh16"},
        {"hsh4", "hsh4"}, {"hsh9", "hsh9"}, {"hsh16", "hsh16"}, {"hsh25", "hsh25"}};
    for (const auto& [spec, name] : valid) {
        const std::optional<model::RtiBasis> basis = model::RtiBasis::parse(spec);
        ASSERT_TRUE(basis) << spec;
        EXPECT_EQ(basis->name(), name);
    }
    for (const char* spec :
         {"", "pt", "ptm7", "ptm:6", "hsh8", "hsh016", "hsh36", "ptm6x", "PTM6", "lrgb", "paper"}) {
        EXPECT_FALSE(model::RtiBasis::parse(spec)) << spec;
    }
}

// A capture of linear float images whose every pixel is an exact `basis` function of the light
// (in [0.1, 0.9] over the capture's lights), with its true coefficients.
struct KnownCapture {
    std::vector<float> coefficients;  // pixel-major, then channel, then term
};

KnownCapture writeKnownCapture(const std::filesystem::path& folder, const model::RtiBasis& basis,
                               const std::vector<proto::Vec3d>& lights, int width, int height) {
    std::filesystem::create_directories(folder);
    const int terms = basis.terms;
    std::vector<std::vector<double>> design(lights.size(), std::vector<double>(terms));
    for (std::size_t s = 0; s < lights.size(); ++s) {
        basis.evaluate(lights[s], design[s].data());
    }
    // The constant term: PTM's last, HSH's first.
    const int constantTerm = basis.kind == model::RtiBasis::Kind::kPtm ? 5 : 0;
    const double constantValue = design[0][static_cast<std::size_t>(constantTerm)];

    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    KnownCapture known;
    known.coefficients.resize(static_cast<std::size_t>(width) * height * 3 * terms);
    std::vector<std::vector<float>> images(
        lights.size(), std::vector<float>(static_cast<std::size_t>(width) * height * 3));
    for (int p = 0; p < width * height; ++p) {
        for (int c = 0; c < 3; ++c) {
            std::vector<double> coefficient(static_cast<std::size_t>(terms));
            for (double& value : coefficient) {
                value = uniform(random);
            }
            std::vector<double> values(lights.size());
            for (std::size_t s = 0; s < lights.size(); ++s) {
                for (int k = 0; k < terms; ++k) {
                    values[s] += coefficient[static_cast<std::size_t>(k)] *
                                 design[s][static_cast<std::size_t>(k)];
                }
            }
            // An affine map of the values into [0.1, 0.9] is one of the coefficients, too.
            const auto [low, high] = std::minmax_element(values.begin(), values.end());
            const double scale = 0.8 / (*high - *low), lowest = *low;
            for (double& value : coefficient) {
                value *= scale;
            }
            coefficient[static_cast<std::size_t>(constantTerm)] +=
                (0.1 - scale * lowest) / constantValue;
            for (int k = 0; k < terms; ++k) {
                known.coefficients[(static_cast<std::size_t>(p) * 3 + c) * terms + k] =
                    static_cast<float>(coefficient[static_cast<std::size_t>(k)]);
            }
            for (std::size_t s = 0; s < lights.size(); ++s) {
                images[s][static_cast<std::size_t>(p) * 3 + c] =
                    static_cast<float>(0.1 + scale * (values[s] - lowest));
            }
        }
    }
    std::ofstream lp(folder / "dirs.lp");
    lp << lights.size() << "\n";
    lp.precision(17);
    for (std::size_t s = 0; s < lights.size(); ++s) {
        const std::string name = "light" + std::to_string(s) + ".exr";
        lp << name << " " << lights[s].x << " " << lights[s].y << " " << lights[s].z << "\n";
        auto out = OIIO::ImageOutput::create(name);
        const std::string path = (folder / name).string();
        EXPECT_TRUE(out &&
                    out->open(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, images[s].data()) && out->close())
            << path;
    }
    return known;
}

class RtiBasisRecovery : public ::testing::TestWithParam<const char*> {};

// The fit is linear least squares on exact data: it gives the coefficients back to float
// precision, and predicts the held-out lights (every 4th) as well.
TEST_P(RtiBasisRecovery, FitRecoversAKnownBasisAndEvalScoresTheHeldOutLights) {
    const model::RtiBasis basis = *model::RtiBasis::parse(GetParam());
    testing::TemporaryFolder folder;
    constexpr int kWidth = 7, kHeight = 5;
    const std::vector<proto::Vec3d> lights = testing::domeLights({15, 35, 55, 75}, 10, 7);
    const KnownCapture known =
        writeKnownCapture(folder / "capture", basis, lights, kWidth, kHeight);
    const std::filesystem::path model = folder / "model.exr";
    const std::string capture = (folder / "capture" / "dirs.lp").string();
    const CommandResult fit = runCommand(vpe({"fit", capture, "--model", GetParam(), "--held-out",
                                              "4", "--out", model.string(), "--json"}));
    ASSERT_EQ(fit.exitStatus, 0) << fit.err;
    const nlohmann::json fitJson = lastJsonLine(fit.out);
    EXPECT_EQ(fitJson.at("images"), 30);  // 40 lights, every 4th held out
    EXPECT_EQ(fitJson.at("basis"), basis.name());
    EXPECT_FALSE(std::filesystem::exists(folder / "model.preview.png"));

    model::ModelReader reader(model, model::ModelKinds::kAny);
    ASSERT_TRUE(reader.info().rtiBasis());
    EXPECT_EQ(reader.info().rtiBasis()->name(), basis.name());
    model::ModelRows rows;
    reader.readRows(0, kHeight, rows);
    double worst = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            for (int c = 0; c < 3; ++c) {
                const float* fitted = rows.coefficientsAt(y, x, c);
                for (int k = 0; k < basis.terms; ++k) {
                    const float truth =
                        known.coefficients[(static_cast<std::size_t>(y * kWidth + x) * 3 + c) *
                                               basis.terms +
                                           k];
                    worst = std::max(worst, std::fabs(static_cast<double>(fitted[k] - truth)));
                }
            }
        }
    }
    std::printf("%s: largest coefficient error %.3g\n", basis.name().c_str(), worst);
    EXPECT_LT(worst, 5e-7) << basis.name();  // measured ≤ 1.2e-7

    const CommandResult eval =
        runCommand(vpe({"eval", model.string(), capture, "--held-out", "4", "--json"}));
    ASSERT_EQ(eval.exitStatus, 0) << eval.err;
    const nlohmann::json json = lastJsonLine(eval.out);
    ASSERT_EQ(json.at("images").size(), 10u);
    EXPECT_EQ(json.at("images")[0].at("name"), "light3.exr");
    // Float images: float rounding only (measured ≤ 5.2e-6 levels; PSNR reports its cap, 100).
    EXPECT_LT(json.at("rms").get<double>(), 1e-5) << json.dump();
    EXPECT_EQ(json.at("psnr").get<double>(), 100.0) << json.dump();
}

INSTANTIATE_TEST_SUITE_P(Bases, RtiBasisRecovery,
                         ::testing::Values("ptm6", "ptm10", "hsh4", "hsh9", "hsh16"));

TEST(RtiBasis, BadModelNamesExitTwoWithOneLine) {
    testing::TemporaryFolder folder;
    writeKnownCapture(folder / "capture", *model::RtiBasis::parse("ptm6"),
                      testing::domeLights({30, 60}, 8), 3, 2);
    for (const char* model : {"ptm7", "hsh:16", "rbf"}) {
        const CommandResult result =
            runCommand(vpe({"fit", (folder / "capture" / "dirs.lp").string(), "--model", model,
                            "--out", (folder / "m.exr").string()}));
        expectInputError(result, {model, "ptm6", "hsh16"});
        EXPECT_FALSE(std::filesystem::exists(folder / "m.exr"));
    }
}

// Too few training lights for the basis: refused before anything is written.
TEST(RtiBasis, TooFewLightsForTheBasisExitTwo) {
    testing::TemporaryFolder folder;
    writeKnownCapture(folder / "capture", *model::RtiBasis::parse("ptm6"),
                      testing::domeLights({30, 60}, 6), 3, 2);
    const CommandResult result =
        runCommand(vpe({"fit", (folder / "capture" / "dirs.lp").string(), "--model", "hsh16",
                        "--out", (folder / "m.exr").string()}));
    expectInputError(result, {"12 images", "hsh16"});
    EXPECT_FALSE(std::filesystem::exists(folder / "m.exr"));
}

// What needs a BRDF refuses an RTI basis fit with one line naming it.
TEST(RtiBasis, BrdfConsumersRefuseAnRtiFit) {
    testing::TemporaryFolder folder;
    writeKnownCapture(folder / "capture", *model::RtiBasis::parse("ptm6"),
                      testing::domeLights({30, 60}, 8), 3, 2);
    const std::filesystem::path model = folder / "m.exr";
    ASSERT_EQ(runCommand(vpe({"fit", (folder / "capture" / "dirs.lp").string(), "--model", "ptm6",
                              "--out", model.string()}))
                  .exitStatus,
              0);
    std::string message;
    try {
        const model::ModelReader reader(model);
    } catch (const std::exception& error) {
        message = error.what();
    }
    EXPECT_NE(message.find("ptm6"), std::string::npos)
        << "not refused, or without naming it: '" << message << "'";
}

// Where a capture is what a classic basis draws and no BRDF does — every pixel a random HSH-9
// function of the light — the extended fit says, on its own training lights over every fold,
// that a classic basis predicts them better; with --fall-back it writes that basis instead.
TEST(RtiBasis, ExtendedFitSaysWhereAClassicBasisPredictsBetterAndFallsBackOnRequest) {
    testing::TemporaryFolder folder;
    writeKnownCapture(folder / "capture", *model::RtiBasis::parse("hsh9"),
                      testing::domeLights({15, 35, 55, 75}, 10, 7), 12, 10);
    const std::string capture = (folder / "capture" / "dirs.lp").string();
    const std::filesystem::path model = folder / "model.exr";
    const CommandResult said = runCommand(vpe({"fit", capture, "--model", "extended", "--held-out",
                                               "4", "--out", model.string(), "--json"}));
    ASSERT_EQ(said.exitStatus, 0) << said.err;
    const nlohmann::json classic = lastJsonLine(said.out).at("classic_bases");
    const std::string better = classic.at("better");
    std::printf("extended %.3f levels, %s\n", classic.at("extended").at("image_rms").get<double>(),
                classic.at("every_fold").dump().c_str());
    EXPECT_TRUE(better == "hsh9" || better == "hsh16") << classic.dump();
    EXPECT_FALSE(classic.at("written_instead").get<bool>());
    EXPECT_NE(said.err.find(better + " predicts this capture's own held-out training lights"),
              std::string::npos)
        << said.err;
    EXPECT_FALSE(model::ModelReader(model, model::ModelKinds::kAny)
                     .info()
                     .rtiBasis());  // the extended model

    const CommandResult fallen =
        runCommand(vpe({"fit", capture, "--model", "extended", "--held-out", "4", "--fall-back",
                        "--out", model.string(), "--json"}));
    ASSERT_EQ(fallen.exitStatus, 0) << fallen.err;
    const nlohmann::json json = lastJsonLine(fallen.out);
    EXPECT_TRUE(json.at("classic_bases").at("written_instead").get<bool>());
    EXPECT_EQ(json.at("basis"), better);
    model::ModelReader reader(model, model::ModelKinds::kAny);
    ASSERT_TRUE(reader.info().rtiBasis());
    EXPECT_EQ(reader.info().rtiBasis()->name(), better);
}

// The RTI protocol of ../shared/data/realrti-dev (every 4th light held out, mean of per-image
// PSNR) on item1, the door: the figures its README states for PTM-6 and HSH-16.
TEST(RtiBasis, RealDataDoorMatchesThePublishedBaselines) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path capture = data / "realrti-dev" / "item1" / "dirs.lp";
    if (!std::filesystem::exists(capture)) {
        GTEST_SKIP() << "realrti-dev/item1 not found under " << data;
    }
    testing::TemporaryFolder folder;
    for (const auto& [model, expected] :
         std::vector<std::pair<std::string, double>>{{"ptm6", 32.74}, {"hsh16", 36.78}}) {
        const std::string out = (folder / (model + ".exr")).string();
        ASSERT_EQ(runCommand(vpe({"fit", capture.string(), "--model", model, "--held-out", "4",
                                  "--out", out}))
                      .exitStatus,
                  0);
        const CommandResult eval =
            runCommand(vpe({"eval", out, capture.string(), "--held-out", "4", "--json"}));
        ASSERT_EQ(eval.exitStatus, 0) << eval.err;
        const nlohmann::json json = lastJsonLine(eval.out);
        EXPECT_EQ(json.at("images").size(), 15u);
        EXPECT_NEAR(json.at("psnr").get<double>(), expected, 0.01) << model;
    }
}

}  // namespace
}  // namespace vpe
