// SPDX-License-Identifier: MIT
// `vpe export-relight`: a fitted model exported to Relight's web format and read back, its
// relit pictures against the model's own predictions; bad input as users meet it.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/relight_web/relight_web_reader.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/synthetic_capture.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::CommandResult;
using testing::runCommand;
constexpr auto& vpe = testing::vpeCommand;

// The JSON report: the last line of stdout.
nlohmann::json lastJson(const std::string& out) {
    const std::size_t end = out.find_last_not_of('\n');
    const std::size_t line = out.rfind('\n', end);
    return nlohmann::json::parse(out.substr(line == std::string::npos ? 0 : line + 1));
}

// A small synthetic capture fitted with the paper's model, shared by the tests below.
class ExportRelight : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        folder_ = new testing::TemporaryFolder();
        testing::SyntheticCaptureSpec spec;
        spec.width = 40;
        spec.height = 32;
        spec.harmonics = 2;
        spec.lights = testing::domeLights({20, 40, 60, 80}, 8, 0);
        spec.format = testing::SyntheticFormat::kPng8Srgb;
        spec.manifest = false;
        writeSyntheticCapture(folder_->path() / "capture", spec);
        const CommandResult fit = runCommand(
            vpe({"fit", capturePath(), "--out", modelPath(), "--harmonics", "2", "--no-preview"}));
        ASSERT_EQ(fit.exitStatus, 0) << fit.err;
    }
    static void TearDownTestSuite() {
        delete folder_;
        folder_ = nullptr;
    }
    static std::string capturePath() { return (folder_->path() / "capture").string(); }
    static std::string modelPath() { return (folder_->path() / "model.exr").string(); }
    static testing::TemporaryFolder* folder_;
};

testing::TemporaryFolder* ExportRelight::folder_ = nullptr;

TEST_F(ExportRelight, ReadsBackCloseToTheModel) {
    const std::filesystem::path out = folder_->path() / "web";
    const CommandResult result = runCommand(
        vpe({"export-relight", modelPath(), capturePath(), "--out", out.string(), "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJson(result.out);
    const relight_web::RelightWebReader reader(out);
    EXPECT_EQ(reader.width(), 40);
    EXPECT_EQ(reader.planes(), 9);
    EXPECT_EQ(reader.resolution(), 8);
    // The capture's lights are recorded, as Relight records them.
    EXPECT_EQ(reader.lights().size(), capture::openCapture(capturePath()).images.size());
    // Measured as OpenLIME shows it (8-bit linear buffer): 35.74 dB mean, 28.63 dB worst (a
    // 20° light) on this capture (R = 8, K = 9, quality 95, least-squares nodes); decoded,
    // before that buffer: 35.80 and 28.63 dB.
    const nlohmann::json& trip = report["round_trip"];
    std::printf(
        "[ measure  ] synthetic round trip as OpenLIME shows it: mean %.2f dB, worst "
        "%.2f dB; decoded %.2f and %.2f dB\n",
        trip["psnr"].get<double>(), trip["worst_psnr"].get<double>(),
        trip["decoded"]["psnr"].get<double>(), trip["decoded"]["worst_psnr"].get<double>());
    EXPECT_EQ(trip["shown_as"], "openlime");
    EXPECT_GT(trip["psnr"].get<double>(), 35.0);
    EXPECT_GT(trip["worst_psnr"].get<double>(), 28.0);
    EXPECT_GT(trip["decoded"]["psnr"].get<double>(), 35.0);
    EXPECT_EQ(trip["per_light"].size(), trip["decoded"]["per_light"].size());
    EXPECT_EQ(trip["below_zero_at_grid"]["values"].get<std::size_t>(), 0u);
}

TEST_F(ExportRelight, RefusesPlaneCountsOpenLimeCannotRead) {
    const std::filesystem::path out = folder_->path() / "bad";
    const CommandResult result = runCommand(vpe(
        {"export-relight", modelPath(), capturePath(), "--out", out.string(), "--planes", "8"}));
    testing::expectInputError(result, {"--planes 8"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(ExportRelight, NamesAMissingModel) {
    const std::string missing = (folder_->path() / "missing.exr").string();
    const CommandResult result = runCommand(
        vpe({"export-relight", missing, capturePath(), "--out", (folder_->path() / "x").string()}));
    testing::expectInputError(result, {missing});
}

// A real capture: realrti-dev item7 (clay relief, dome, 48 lights, 310×310), fitted with the
// paper's model on the training lights, exported, compared under the held-out lights.
TEST(ExportRelightRealData, Item7HeldOutLights) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path capture = data / "realrti-dev/item7";
    if (!std::filesystem::exists(capture / "dirs.lp")) {
        GTEST_SKIP() << "realrti-dev/item7 not found under " << data;
    }
    testing::TemporaryFolder folder;
    const CommandResult fit =
        runCommand(vpe({"fit", capture.string(), "--out", (folder / "model.exr").string(),
                        "--model", "paper", "--held-out", "4", "--no-preview"}));
    ASSERT_EQ(fit.exitStatus, 0) << fit.err;
    const CommandResult result =
        runCommand(vpe({"export-relight", (folder / "model.exr").string(), capture.string(),
                        "--out", (folder / "web").string(), "--held-out", "4", "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJson(result.out);
    const nlohmann::json& trip = report["round_trip"];
    std::printf(
        "[ measure  ] item7 held-out round trip as OpenLIME shows it: mean %.2f dB, worst "
        "%.2f dB; decoded %.2f and %.2f dB; %zu bytes\n",
        trip["psnr"].get<double>(), trip["worst_psnr"].get<double>(),
        trip["decoded"]["psnr"].get<double>(), trip["decoded"]["worst_psnr"].get<double>(),
        report["bytes"].get<std::size_t>());
    EXPECT_EQ(trip["lights"].get<int>(), 12);
    // Measured as OpenLIME shows it: 39.38 dB mean, 22.50 dB worst (image11, 6° above the
    // horizon); decoded 38.72 / 22.87 dB. Before the light field was kept non-negative: 39.36
    // / 24.83 dB shown, 39.43 / 24.97 dB decoded.
    EXPECT_GT(trip["psnr"].get<double>(), 38.5);
    EXPECT_EQ(trip["below_zero_at_grid"]["values"].get<std::size_t>(), 0u);
}

}  // namespace
}  // namespace vpe
