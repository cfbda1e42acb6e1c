// SPDX-License-Identifier: MIT
// `vpe info` as users run it: what it reports about a bundle the writer made, and exit
// status 2 with one line naming the file when the bundle is bad.
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/bake/bundle_writer.h"
#include "vpe/proto/bundle_format.h"

#include "offline/bake/bundle_sample.h"
#include "support/command_runner.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using testing::CommandResult;
using testing::runCommand;

CommandResult vpeInfo(const std::vector<std::string>& arguments) {
    std::vector<std::string> command{testing::vpeExecutable(), "info"};
    command.insert(command.end(), arguments.begin(), arguments.end());
    return runCommand(command);
}

void expectOneLineError(const CommandResult& result, const std::string& message) {
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_EQ(result.err, "vpe: " + message + "\n");
    EXPECT_EQ(result.out, "");
}

class InfoCommand : public ::testing::Test {
protected:
    void SetUp() override { bake::writeBundle(path_, testing::sampleBundleContents()); }

    std::vector<char> bytes() const {
        std::ifstream stream(path_, std::ios::binary);
        return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    }
    void rewrite(const std::vector<char>& bytes) const {
        std::ofstream stream(path_, std::ios::binary | std::ios::trunc);
        stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }

    testing::TemporaryFolder folder_;
    std::filesystem::path path_ = folder_ / "scene.vpeb";
};

TEST_F(InfoCommand, DescribesTheBundle) {
    const CommandResult result = vpeInfo({path_.string()});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const std::string& out = result.out;
    for (const std::string& expected : std::vector<std::string>{
             path_.string() + ": vpe bundle 1." + std::to_string(proto::kBundleMinorVersion) + ", ",
             "checksum 0x", " OK\n", "mesh       4 vertices, 2 triangles\n",
             "projector  1280 x 800, fx 1500.5 fy 1498 ", "camera     none\n",
             "viewer     (0, 0.25, 1.75) m\n", "response   curve, 4/4/4 samples",
             "model      M = 2, lambda = 0.5, 18 values per texel (fourier_brdf:k_major_rgb)\n",
             "           theta basis: 2 functions (orthonormal over [0, π])\n",
             "textures   5 x 3, 2 regions, sampling wraps in u\n",
             "  region 0 'base': full, 5 RGBA16F layers, 40 bytes per texel\n",
             "  region 1 'glaze': low_rank, rank 5, 2 RGBA16F layers, 16 bytes per texel\n",
             "  composed: full, 5 RGBA16F layers, 40 bytes per texel\n", "presets    2\n",
             "  preset 0 'stripes': unorm8, 2 bytes per texel\n",
             "  preset 1 'fade': float16, 4 bytes per texel\n"}) {
        EXPECT_NE(out.find(expected), std::string::npos) << "'" << expected << "' not in:\n" << out;
    }
}

TEST_F(InfoCommand, ReportsJson) {
    const CommandResult result = vpeInfo({path_.string(), "--json"});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json json = nlohmann::json::parse(result.out);
    EXPECT_EQ(json["file"], path_.string());
    EXPECT_EQ(json["format_version"], "1." + std::to_string(proto::kBundleMinorVersion));
    EXPECT_TRUE(json["blend"].is_null());
    EXPECT_TRUE(json["camera"].is_null());
    EXPECT_EQ(json["textures"]["wrap_u"], true);
    EXPECT_EQ(json["file_bytes"], std::filesystem::file_size(path_));
    EXPECT_EQ(json["checksum_ok"], true);
    EXPECT_EQ(json["mesh"]["vertices"], 4);
    EXPECT_EQ(json["mesh"]["triangles"], 2);
    EXPECT_EQ(json["projector"]["width"], 1280);
    EXPECT_EQ(json["projector"]["intrinsics"][0], 1500.5);
    EXPECT_EQ(json["projector"]["translation"][2], 1.2);
    EXPECT_EQ(json["settings"]["response"]["kind"], "curve");
    EXPECT_EQ(json["settings"]["peak_irradiance"], 2.5);
    EXPECT_EQ(json["model"]["harmonics"], 2);
    EXPECT_EQ(json["model"]["coefficients_per_texel"], 18);
    EXPECT_EQ(json["model"]["theta_basis"], 2);
    EXPECT_EQ(json["textures"]["width"], 5);
    ASSERT_EQ(json["textures"]["regions"].size(), 2u);
    EXPECT_EQ(json["textures"]["regions"][1]["name"], "glaze");
    EXPECT_EQ(json["textures"]["regions"][1]["encoding"], "low_rank");
    EXPECT_EQ(json["textures"]["regions"][1]["rank"], 5);
    EXPECT_EQ(json["textures"]["regions"][1]["bytes_per_texel"], 16);
    EXPECT_EQ(json["textures"]["composed"]["encoding"], "full");
    ASSERT_EQ(json["presets"].size(), 2u);
    EXPECT_EQ(json["presets"][1]["encoding"], "float16");
}

TEST_F(InfoCommand, SaysABundleWithoutThetaBasisRendersExactly) {
    bake::BundleContents contents = testing::sampleBundleContents();
    contents.model.thetaBasis.clear();
    bake::writeBundle(path_, contents);
    const CommandResult text = vpeInfo({path_.string()});
    ASSERT_EQ(text.exitStatus, 0) << text.err;
    EXPECT_NE(text.out.find("           theta basis: none: rendered exactly\n"), std::string::npos)
        << text.out;
    const CommandResult json = vpeInfo({path_.string(), "--json"});
    ASSERT_EQ(json.exitStatus, 0) << json.err;
    EXPECT_EQ(nlohmann::json::parse(json.out)["model"]["theta_basis"], "full");
}

TEST_F(InfoCommand, ShowsTheInstallationsCamera) {
    bake::BundleContents contents = testing::sampleBundleContents();
    proto::ProjectorCalibration camera;
    camera.width = 1640;
    camera.height = 1232;
    camera.intrinsics = {1250, 0, 819.5, 0, 1252, 615.5, 0, 0, 1};
    camera.distortion = {-0.12, 0.08, 0, 0, 0};
    camera.rotation = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    camera.translation = {0.02, -0.1, 2.4};
    contents.camera = camera;
    bake::writeBundle(path_, contents);
    const CommandResult text = vpeInfo({path_.string()});
    ASSERT_EQ(text.exitStatus, 0) << text.err;
    EXPECT_NE(text.out.find("camera     1640 x 1232, fx 1250 fy 1252 cx 819.5 cy 615.5, "
                            "distortion -0.12 0.08 0 0 0\n"
                            "           R rows (1, 0, 0) (0, 0, -1) (0, 1, 0), T (0.02, -0.1, "
                            "2.4) m\n"),
              std::string::npos)
        << text.out;
    const CommandResult json = vpeInfo({path_.string(), "--json"});
    ASSERT_EQ(json.exitStatus, 0) << json.err;
    const nlohmann::json report = nlohmann::json::parse(json.out);
    EXPECT_EQ(report["camera"]["width"], 1640);
    EXPECT_EQ(report["camera"]["height"], 1232);
    EXPECT_EQ(report["camera"]["intrinsics"][5], 615.5);
    EXPECT_EQ(report["camera"]["rotation"][5], -1);
    EXPECT_EQ(report["camera"]["translation"][2], 2.4);
    EXPECT_EQ(report["projector"]["width"], 1280);
}

TEST_F(InfoCommand, RefusesACorruptBundleWithStatus2) {
    std::vector<char> corrupt = bytes();
    corrupt[corrupt.size() - 3] ^= 0x10;
    rewrite(corrupt);
    const CommandResult result = vpeInfo({path_.string()});
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_TRUE(result.err.starts_with("vpe: " + path_.string() + ": checksum mismatch: "))
        << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

TEST_F(InfoCommand, RefusesATruncatedBundleWithStatus2) {
    const std::vector<char> whole = bytes();
    rewrite(std::vector<char>(whole.begin(), whole.begin() + 1000));
    expectOneLineError(vpeInfo({path_.string()}), path_.string() + ": truncated: header says " +
                                                      std::to_string(whole.size()) +
                                                      " bytes, file has 1000");
}

TEST_F(InfoCommand, RefusesAMissingFileWithStatus2) {
    const std::filesystem::path missing = folder_ / "missing.vpeb";
    expectOneLineError(vpeInfo({missing.string()}),
                       missing.string() + ": cannot open: No such file or directory");
}

}  // namespace
}  // namespace vpe
