// SPDX-License-Identifier: MIT
// vpe bake end to end: a fitted synthetic model and a quilt folder baked onto the built-in
// vase with the demo projector; what the device reads back (mesh UVs flipped to rows from the
// top, low-rank textures decoding to the model within the stated error, presets summing to
// one, the θs basis the device renders in); and the bad-input contract. Also the half-float
// decoder against Eigen's encoder.
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <Eigen/Core>
#include <Imath/half.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/bake/bake_inputs.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/half_float.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/projector_calibration.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/fitted_capture.h"
#include "support/test_data.h"
#include "support/vpe_command_names.h"

namespace vpe {
namespace {

using namespace testing::vpe_command_names;  // NOLINT: support/vpe_command_names.h

TEST(HalfFloat, DecodesEveryHalfAsEigenEncodesIt) {
    for (float value : {0.0f, -0.0f, 1.0f, -2.5f, 65504.0f, 6.1e-5f, 5.96e-8f, 3.0e-6f, 0.3333f,
                        INFINITY, -INFINITY}) {
        const Eigen::half half(value);
        const std::uint16_t bits = Eigen::numext::bit_cast<std::uint16_t>(half);
        EXPECT_EQ(proto::halfToFloat(bits), static_cast<float>(half)) << value;
    }
    for (std::uint32_t bits = 0; bits < 0x7c00u; bits += 7) {  // every 7th finite positive half
        const Eigen::half half =
            Eigen::numext::bit_cast<Eigen::half>(static_cast<std::uint16_t>(bits));
        EXPECT_EQ(proto::halfToFloat(static_cast<std::uint16_t>(bits)), static_cast<float>(half));
    }
}

// The one float → half encoder (proto::floatToHalf: the bake, the test bundles) against
// OpenEXR's Imath, which the model files use: every float bit pattern in steps of 61 (70 M
// values across every exponent, both signs), and each half's exact midpoints to its
// neighbours and the floats beside them, where ties go to even.
TEST(HalfFloat, EncodesEveryFloatAsImathDoes) {
    const auto check = [](std::uint32_t bits) {
        const float value = std::bit_cast<float>(bits);
        if (std::isnan(value)) {
            const std::uint16_t half = proto::floatToHalf(value);
            EXPECT_TRUE((half & 0x7c00u) == 0x7c00u && (half & 0x3ffu) != 0) << bits;
            return true;
        }
        const std::uint16_t expected = imath_float_to_half(value);
        const std::uint16_t got = proto::floatToHalf(value);
        EXPECT_EQ(got, expected) << "float bits 0x" << std::hex << bits;
        return got == expected;
    };
    for (std::uint64_t bits = 0; bits <= 0xffffffffull; bits += 61) {
        if (!check(static_cast<std::uint32_t>(bits))) {
            return;  // one report, not millions
        }
    }
    for (std::uint32_t h = 0; h < 0x7bffu; ++h) {
        const double midpoint =
            (static_cast<double>(proto::halfToFloat(static_cast<std::uint16_t>(h))) +
             static_cast<double>(proto::halfToFloat(static_cast<std::uint16_t>(h + 1)))) /
            2.0;
        const auto mid = std::bit_cast<std::uint32_t>(static_cast<float>(midpoint));
        for (const std::uint32_t bits : {mid - 1, mid, mid + 1, mid | 0x80000000u}) {
            if (!check(bits)) {
                return;
            }
        }
    }
}

class Bake : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        folder_ = new testing::TemporaryFolder;
        if (testing::suiteRunsMoreThanItsRefusals()) {
            ASSERT_NO_FATAL_FAILURE(
                testing::synthesizeAndFit(path("capture"), path("model.exr"), 48));
        }
    }
    static void TearDownTestSuite() {
        delete folder_;
        folder_ = nullptr;
    }
    static std::string path(const std::string& name) { return (*folder_ / name).string(); }
    // The refusals' model: a small fit that every refusal shares (testing::smallFittedCapture).
    static std::string smallModel() {
        return (testing::smallFittedCapture() / "model.exr").string();
    }
    static testing::TemporaryFolder* folder_;
};

testing::TemporaryFolder* Bake::folder_ = nullptr;

TEST_F(Bake, ATextureOnTheVaseReadsBackAsTheDeviceSeesIt) {
    const testing::CommandResult result =
        runCommand(vpe({"bake", "--texture", path("model.exr"), "--rank", "8", "--out",
                        path("scene.vpeb"), "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJsonLine(result.out);
    EXPECT_EQ(report["regions"], 1);
    EXPECT_EQ(report["bytes_per_texel"], 16);
    EXPECT_GT(report["explained_variance"].get<double>(), 0.99);
    // The θs basis: 4 functions by default, fitted to the decoded low-rank code; they keep
    // 0.9966 of the θs parts' ∫₀^π g² here (measured; 0.942 with 1 function, 0.998 with 6).
    EXPECT_EQ(report["theta_basis"], 4);
    EXPECT_GT(report["theta_energy_kept"].get<double>(), 0.99);
    EXPECT_LE(report["theta_energy_kept"].get<double>(), 1.0);

    const proto::BundleFile file = proto::BundleFile::open(path("scene.vpeb"));
    const proto::BundleView& view = file.view();
    EXPECT_EQ(view.textureWidth(), 48);
    EXPECT_EQ(view.model().harmonics, 10);
    ASSERT_EQ(view.regions().size(), 1u);
    ASSERT_EQ(view.presets().size(), 1u);
    EXPECT_GT(view.mesh().triangleCount(), 1000u);
    EXPECT_EQ(view.model().thetaBasisSize(), 4);
    EXPECT_EQ(proto::checkThetaBasis(10, view.model().thetaBasis), "");
    // The fit's relief travels into the bundle (format 1.2): x and y of its detail normals.
    EXPECT_TRUE(report["relief"].get<bool>());
    EXPECT_EQ(view.header().minorVersion, proto::kBundleMinorVersion);
    // The demo projector has no camera beside it: none in the bundle.
    EXPECT_FALSE(report["camera"].get<bool>());
    EXPECT_FALSE(view.camera().has_value());
    EXPECT_NE(result.err.find(", no camera, "), std::string::npos) << result.err;
    const std::vector<float> relief =
        bake::bundleDetailNormals(model::readCoefficientImage(path("model.exr")));
    ASSERT_EQ(view.regions()[0].coefficients.detailNormals.size(), relief.size());
    for (std::size_t i = 0; i < relief.size(); i += 7) {
        EXPECT_NEAR(proto::halfToFloat(view.regions()[0].coefficients.detailNormals[i]), relief[i],
                    5e-4)
            << i;
    }
    // The vase's UVs are OBJ-style (v up); the bundle's rows run from the top.
    const scene::ScreenMesh vase = scene::makeProceduralVase();
    for (std::size_t i = 0; i < vase.uvs.size(); i += 97) {
        EXPECT_FLOAT_EQ(view.mesh().uvs[2 * i + 1], 1.0f - vase.uvs[i].y);
    }
    // Low-rank decoding reproduces the model's coefficients.
    const std::vector<float> values =
        bake::bundleCoefficients(model::readCoefficientImage(path("model.exr")));
    const proto::CoefficientMapView& map = view.regions()[0].coefficients;
    ASSERT_EQ(map.encoding, proto::CoefficientEncoding::kLowRank);
    ASSERT_EQ(map.rank, 8);
    const int c = view.model().coefficientsPerTexel();
    const std::size_t texels = 48 * 48;
    double squared = 0, variance = 0;
    for (std::size_t t = 0; t < texels; ++t) {
        for (int k = 0; k < c; ++k) {
            double value = map.mean[static_cast<std::size_t>(k)];
            for (int r = 0; r < map.rank; ++r) {
                const std::size_t layer = static_cast<std::size_t>(r / 4);
                const std::uint16_t w =
                    map.layers.halves[(layer * texels + t) * 4 + static_cast<std::size_t>(r % 4)];
                value += static_cast<double>(proto::halfToFloat(w)) *
                         map.basis[static_cast<std::size_t>(r * c + k)];
            }
            const double truth =
                values[t * static_cast<std::size_t>(c) + static_cast<std::size_t>(k)];
            squared += (value - truth) * (value - truth);
            variance += (truth - map.mean[static_cast<std::size_t>(k)]) *
                        (truth - map.mean[static_cast<std::size_t>(k)]);
        }
    }
    const double reported = report["coefficient_rms"].get<double>();
    const double decoded =
        std::sqrt(squared / static_cast<double>(texels * static_cast<std::size_t>(c)));
    EXPECT_LT(decoded, 1.05 * reported + 1e-4);  // half-float weights add at most rounding
    EXPECT_LT(squared, 0.01 * variance);
}

TEST_F(Bake, ThetaBasisSizeOrNone) {
    const auto bake = [&](const std::string& size, const std::string& name) {
        const testing::CommandResult result =
            runCommand(vpe({"bake", "--texture", path("model.exr"), "--encoding", "full",
                            "--theta-basis", size, "--out", path(name), "--json"}));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        return lastJsonLine(result.out);
    };
    const nlohmann::json full = bake("full", "exact.vpeb");
    EXPECT_EQ(full["theta_basis"], "full");
    EXPECT_EQ(full["theta_energy_kept"], 1.0);
    EXPECT_TRUE(proto::BundleFile::open(path("exact.vpeb"))->model().thetaBasis.empty());
    EXPECT_EQ(bake("0", "zero.vpeb")["theta_basis"], "full");
    EXPECT_TRUE(proto::BundleFile::open(path("zero.vpeb"))->model().thetaBasis.empty());

    // More functions keep more; the full encoding is fitted as stored.
    double previous = 0;
    for (int size : {1, 2, 6, 18}) {
        const std::string name = "k" + std::to_string(size) + ".vpeb";
        const nlohmann::json report = bake(std::to_string(size), name);
        EXPECT_EQ(report["theta_basis"], size);
        const double kept = report["theta_energy_kept"].get<double>();
        EXPECT_GT(kept, previous) << size;
        previous = kept;
        const proto::BundleFile file = proto::BundleFile::open(path(name));
        EXPECT_EQ(file->model().thetaBasisSize(), size);
        EXPECT_EQ(proto::checkThetaBasis(10, file->model().thetaBasis), "") << size;
    }
    EXPECT_GT(previous, 1.0 - 1e-9);  // 18 functions: all that M = 10 has over [0, π]
}

TEST_F(Bake, QuiltRegionsWithPresets) {
    // A quilt folder is region maps of one size: the model twice will do.
    std::filesystem::create_directories(path("quilt"));
    std::filesystem::copy_file(path("model.exr"), path("quilt/region0.exr"));
    std::filesystem::copy_file(path("model.exr"), path("quilt/region1.exr"));
    const testing::CommandResult result = runCommand(vpe(
        {"bake", "--quilt", path("quilt"), "--preset",
         "half=stripes:period=8,stripes:period=8:invert", "--preset",
         "left=constant,constant:value=0", "--encoding", "full", "--out", path("regions.vpeb")}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const proto::BundleFile file = proto::BundleFile::open(path("regions.vpeb"));
    const proto::BundleView& view = file.view();
    ASSERT_EQ(view.regions().size(), 2u);
    EXPECT_EQ(view.regions()[0].coefficients.encoding, proto::CoefficientEncoding::kFull);
    ASSERT_EQ(view.presets().size(), 2u);
    EXPECT_EQ(view.presets()[1].name, "left");
    const std::size_t texels = 48 * 48;
    for (std::size_t t = 0; t < texels; ++t) {
        EXPECT_EQ(view.presets()[0].unorm8[t] + view.presets()[0].unorm8[texels + t], 255);
        EXPECT_EQ(view.presets()[1].unorm8[t], 255);
    }
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// A procam calibration with the camera's keys: the bundle carries the camera (format 1.3), at
// the origin of the procam frame; a projector-only file gives none.
TEST_F(Bake, RecordsTheCameraOfAProcamCalibration) {
    const scene::ProjectorCalibration projector =
        scene::projectorLookingAt(160, 120, 30.0, {0.1, 0.1, 0.6}, {0, 0.075, 0});
    proto::PinholeCamera camera;
    camera.width = 1640;
    camera.height = 1232;
    camera.K = {1250, 0, 819.5, 0, 1252, 615.5, 0, 0, 1};
    camera.distortion = {-0.12, 0.08, 0.0004, -0.0003, -0.01};
    scene::writeProcamCalibration(projector, camera, 0.3, path("procam.yml"));
    const testing::CommandResult result =
        runCommand(vpe({"bake", "--texture", path("model.exr"), "--projector", path("procam.yml"),
                        "--theta-basis", "full", "--out", path("camera.vpeb"), "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    EXPECT_TRUE(lastJsonLine(result.out)["camera"].get<bool>());
    EXPECT_NE(result.err.find(", camera 1640x1232, "), std::string::npos) << result.err;
    const proto::BundleFile file = proto::BundleFile::open(path("camera.vpeb"));
    ASSERT_TRUE(file->camera().has_value());
    const proto::ProjectorCalibration& baked = *file->camera();
    EXPECT_EQ(baked.width, 1640u);
    EXPECT_EQ(baked.height, 1232u);
    EXPECT_EQ(baked.intrinsics, camera.K);
    EXPECT_EQ(baked.distortion, camera.distortion);
    EXPECT_EQ(baked.rotation, (std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
    EXPECT_EQ(baked.translation, (std::array<double, 3>{0, 0, 0}));
    EXPECT_EQ(file->projector().width, 160u);

    scene::writeProjectorCalibration(projector, path("projector-only.yml"));
    const testing::CommandResult without = runCommand(
        vpe({"bake", "--texture", path("model.exr"), "--projector", path("projector-only.yml"),
             "--theta-basis", "full", "--out", path("no-camera.vpeb"), "--json"}));
    ASSERT_EQ(without.exitStatus, 0) << without.err;
    EXPECT_FALSE(lastJsonLine(without.out)["camera"].get<bool>());
    EXPECT_FALSE(proto::BundleFile::open(path("no-camera.vpeb"))->camera().has_value());

    // A camera that cannot be one is refused, one line naming the file and the key, and no
    // bundle is written.
    writeText(path("bad-camera.yml"),
              "%YAML:1.0\nproj_width: 160\nproj_height: 120\n"
              "proj_K: [200, 0, 79.5, 0, 200, 59.5, 0, 0, 1]\nR: [0, 0, 0]\n"
              "T: [0, 0, 1]\ncam_width: 640\ncam_height: 480\n"
              "cam_K: [500, 0, 319.5, 0, -500, 239.5, 0, 0, 1]\n");
    expectInputError(runCommand(vpe({"bake", "--texture", path("model.exr"), "--projector",
                                     path("bad-camera.yml"), "--out", path("bad-camera.vpeb")})),
                     {"bad-camera.yml", "cam_K: focal lengths must be positive"});
    EXPECT_FALSE(std::filesystem::exists(path("bad-camera.vpeb")));
    writeText(path("sizeless-camera.yml"),
              "%YAML:1.0\nproj_width: 160\nproj_height: 120\n"
              "proj_K: [200, 0, 79.5, 0, 200, 59.5, 0, 0, 1]\nR: [0, 0, 0]\n"
              "T: [0, 0, 1]\ncam_K: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]\n");
    expectInputError(
        runCommand(vpe({"bake", "--texture", path("model.exr"), "--projector",
                        path("sizeless-camera.yml"), "--out", path("bad-camera.vpeb")})),
        {"sizeless-camera.yml", "cam_width: missing"});
}

TEST_F(Bake, BadInputExitsTwoNamingItAndWritesNothing) {
    const std::string out = path("bad/scene.vpeb");
    expectInputError(runCommand(vpe({"bake", "--out", out})), {"--texture", "--quilt"});
    expectInputError(runCommand(vpe({"bake", "--quilt", path("quilt"), "--out", out})),
                     {"--preset"});
    expectInputError(runCommand(vpe({"bake", "--texture", path("missing.exr"), "--out", out})),
                     {"missing.exr"});
    expectInputError(runCommand(vpe({"bake", "--texture", smallModel(), "--mesh", path("none.obj"),
                                     "--out", out})),
                     {"none.obj"});
    expectInputError(runCommand(vpe({"bake", "--texture", smallModel(), "--projector",
                                     path("none.yml"), "--out", out})),
                     {"none.yml"});
    expectInputError(
        runCommand(vpe({"bake", "--texture", smallModel(), "--response", "0", "--out", out})),
        {"response"});
    expectInputError(
        runCommand(vpe({"bake", "--texture", smallModel(), "--viewer", "1,2", "--out", out})),
        {"--viewer"});
    expectInputError(
        runCommand(vpe({"bake", "--texture", smallModel(), "--rank", "0", "--out", out})),
        {"rank"});
    // θs bases: more than 2M + 1 = 21 functions, more than the 18 independent ones, not a size.
    for (const char* size : {"99", "19", "-1", "four"}) {
        expectInputError(runCommand(vpe({"bake", "--texture", smallModel(), "--theta-basis", size,
                                         "--out", out})),
                         {"--theta-basis", size});
    }
    EXPECT_FALSE(std::filesystem::exists(out));
}

// vpe render on a small projector (160 × 120) so the CPU reference stays quick under ASan.
class Render : public Bake {
protected:
    static void SetUpTestSuite() {
        Bake::SetUpTestSuite();
        const scene::ProjectorCalibration projector =
            scene::projectorLookingAt(160, 120, 30.0, {0.1, 0.1, 0.6}, {0, 0.075, 0});
        scene::writeProjectorCalibration(projector, path("projector.yml"));
        // The refusals, alone in their process, bake the small shared fit instead.
        const std::string model =
            testing::suiteRunsMoreThanItsRefusals() ? path("model.exr") : smallModel();
        // Without the relief: its detail is finer than this projector's pixels, and what the
        // loop measures is the simulation, not how much of the texture 160 × 120 pixels can
        // draw (with it: 38.4 dB, 2.5% mean relative error).
        ASSERT_EQ(runCommand(vpe({"bake", "--texture", model, "--projector", path("projector.yml"),
                                  "--relief", "off", "--out", path("small.vpeb")}))
                      .exitStatus,
                  0);
    }
};

TEST_F(Render, WritesTheFrameAndPreviewsThatCloseTheLoop) {
    const testing::CommandResult result = runCommand(vpe(
        {"render", path("small.vpeb"), "--light", "0.3,0.4,0.6", "--gain", "auto", "--out",
         path("frame.png"), "--exr", path("frame.exr"), "--simulate", path("visitor.png"),
         "--direct", path("material.png"), "--view-size", "120x90", "--view-fov", "14", "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json report = lastJsonLine(result.out);
    EXPECT_EQ(report["width"], 160);
    EXPECT_EQ(report["height"], 120);
    EXPECT_GT(report["covered_pixels"].get<int>(), 1000);
    // --gain auto: at most 0.5% of the object's pixels clip, and the gain is at most 1.
    EXPECT_LE(report["clipped_fraction"].get<double>(), 0.005);
    EXPECT_LE(report["gain"].get<double>(), 1.0);
    // What a visitor sees is the material, away from clipping and silhouettes.
    EXPECT_GT(report["loop"]["compared_pixels"].get<int>(), 1000);
    EXPECT_GT(report["loop"]["psnr"].get<double>(), 40.0);
    EXPECT_LT(report["loop"]["mean_relative_error"].get<double>(), 0.02);
    for (const char* file : {"frame.png", "frame.exr", "visitor.png", "material.png"}) {
        EXPECT_TRUE(std::filesystem::exists(path(file))) << file;
    }
}

// The bundle's gain is what vpe render uses unless --gain says otherwise.
TEST_F(Render, UsesTheBundlesGainUnlessToldOtherwise) {
    ASSERT_EQ(runCommand(vpe({"bake", "--texture", path("model.exr"), "--projector",
                              path("projector.yml"), "--gain", "0.25", "--out", path("gain.vpeb")}))
                  .exitStatus,
              0);
    const auto gainOf = [&](std::vector<std::string> extra) {
        std::vector<std::string> arguments = {"render", path("gain.vpeb"), "--light", "0.3,0.4,0.6",
                                              "--out",  path("gain.png"),  "--json"};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        const testing::CommandResult result = runCommand(vpe(arguments));
        EXPECT_EQ(result.exitStatus, 0) << result.err;
        return lastJsonLine(result.out)["gain"].get<double>();
    };
    EXPECT_DOUBLE_EQ(gainOf({}), 0.25);
    EXPECT_DOUBLE_EQ(gainOf({"--gain", "0.5"}), 0.5);
}

TEST_F(Render, BadInputExitsTwoNamingIt) {
    const std::string out = path("bad/frame.png");
    // A bundle with one byte flipped fails its checksum.
    std::filesystem::copy_file(path("small.vpeb"), path("flipped.vpeb"),
                               std::filesystem::copy_options::overwrite_existing);
    {
        std::FILE* file = std::fopen(path("flipped.vpeb").c_str(), "r+b");
        ASSERT_NE(file, nullptr);
        std::fseek(file, -10, SEEK_END);
        const int byte = std::fgetc(file);
        std::fseek(file, -10, SEEK_END);
        std::fputc(byte ^ 0x40, file);
        std::fclose(file);
    }
    expectInputError(
        runCommand(vpe({"render", path("flipped.vpeb"), "--light", "0,0,1", "--out", out})),
        {"flipped.vpeb", "checksum"});
    expectInputError(
        runCommand(vpe({"render", path("none.vpeb"), "--light", "0,0,1", "--out", out})),
        {"none.vpeb"});
    expectInputError(
        runCommand(vpe({"render", path("small.vpeb"), "--light", "0,0", "--out", out})),
        {"--light"});
    expectInputError(runCommand(vpe({"render", path("small.vpeb"), "--light", "0,0,1", "--weights",
                                     "nope", "--out", out})),
                     {"nope"});
    expectInputError(runCommand(vpe({"render", path("small.vpeb"), "--light", "0,0,1", "--gain",
                                     "-1", "--out", out})),
                     {"--gain"});
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace vpe
