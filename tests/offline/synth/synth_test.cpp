// SPDX-License-Identifier: MIT
// vpe synth: the reference renderer against closed forms, determinism, and exactness of a
// fit when the truth is the Fourier model itself.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/common/input_error.h"
#include "vpe/eval/model_evaluation.h"
#include "vpe/fit/capture_fitter.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/synth/capture_synthesizer.h"
#include "vpe/synth/microfacet_brdf.h"
#include "vpe/text/line_reader.h"

#include "support/test_data.h"

namespace vpe::synth {
namespace {

TEST(MicrofacetBrdf, FlatPatchLitHeadOnHasTheClosedForm) {
    // n = l = v: D = 1/(πα²), V = 1/4, F = f0, so π f_spec = f0 / (4α²).
    MicrofacetMaterial material;
    material.albedo = {0.2, 0.4, 0.6};
    material.roughness = 0.3;
    material.f0 = 0.04;
    const proto::Vec3d z{0, 0, 1};
    const proto::Vec3d radiance = microfacetRadiance(material, z, z, z);
    const double specular = 0.04 / (4 * 0.3 * 0.3);
    EXPECT_NEAR(radiance.x, 0.2 + specular, 1e-12);
    EXPECT_NEAR(radiance.y, 0.4 + specular, 1e-12);
    EXPECT_NEAR(radiance.z, 0.6 + specular, 1e-12);
}

TEST(MicrofacetBrdf, DiffusePartIsAlbedoTimesCosine) {
    // Two materials that differ only in albedo differ by Δρ · cos θ, whatever the lobe does.
    MicrofacetMaterial dark, light;
    dark.albedo = {0.1, 0.1, 0.1};
    light.albedo = {0.6, 0.6, 0.6};
    const double e = 60.0 * M_PI / 180.0;
    const proto::Vec3d toLight{std::cos(e), 0, std::sin(e)};
    const proto::Vec3d n{0, 0, 1}, v = proto::normalized(proto::Vec3d{0.2, 0.1, 1.0});
    EXPECT_NEAR(
        microfacetRadiance(light, n, toLight, v).x - microfacetRadiance(dark, n, toLight, v).x,
        0.5 * std::sin(e), 1e-12);
    // Below the horizon nothing is reflected.
    EXPECT_EQ(microfacetRadiance(light, n, proto::normalized(proto::Vec3d{1, 0, -0.1}), v).x, 0.0);
}

TEST(MicrofacetBrdf, IsReciprocal) {
    MicrofacetMaterial material;
    material.roughness = 0.2;
    const proto::Vec3d n{0, 0, 1};
    const proto::Vec3d a = proto::normalized(proto::Vec3d{0.3, 0.1, 0.9});
    const proto::Vec3d b = proto::normalized(proto::Vec3d{-0.5, 0.2, 0.7});
    // f(a, b) = radiance / cos: swapping light and view must not change f.
    const double fab = microfacetRadiance(material, n, a, b).x / proto::dot(n, a);
    const double fba = microfacetRadiance(material, n, b, a).x / proto::dot(n, b);
    EXPECT_NEAR(fab, fba, 1e-12);
}

SynthOptions smallOptions(const std::filesystem::path& out) {
    SynthOptions options;
    options.out = out;
    options.size = 24;
    options.threads = 2;
    return options;
}

TEST(Synth, ImagesEqualTheClosedFormAtSampledPixels) {
    testing::TemporaryFolder folder;
    SynthOptions options = smallOptions(folder / "capture");
    options.encoding = SynthEncoding::kExr;  // no quantization
    options.shadows = false;
    synthesizeCapture(options);
    const image::FloatImage normals = image::readImage(folder / "capture/truth/normals.exr");
    const image::FloatImage positions = image::readImage(folder / "capture/truth/positions.exr");
    const image::FloatImage parameters = image::readImage(folder / "capture/truth/parameters.exr");
    std::ifstream manifestFile(folder / "capture/train/capture.json");
    const nlohmann::json manifest = nlohmann::json::parse(manifestFile);
    const double reference = manifest["lights"]["reference_distance"];
    const std::vector<double> t = manifest["camera"]["translation"];
    const proto::Vec3d camera{0, 0, t[2]};  // rotation diag(1, −1, −1): centre (0, 0, t_z)
    int checked = 0;
    for (int image : {0, 137, 300}) {
        const auto& entry = manifest["images"][static_cast<std::size_t>(image)];
        const std::vector<double> l = entry["light"];
        const image::FloatImage rendered =
            image::readImage(folder / "capture/train" / entry["file"].get<std::string>());
        for (int y : {5, 12, 19}) {
            for (int x : {4, 12, 20}) {
                const proto::Vec3d n{normals.at(x, y, 0), normals.at(x, y, 1), normals.at(x, y, 2)};
                const proto::Vec3d p{positions.at(x, y, 0), positions.at(x, y, 1),
                                     positions.at(x, y, 2)};
                const proto::Vec3d d{l[0] - p.x, l[1] - p.y, l[2] - p.z};
                const double irradiance = reference * reference / proto::dot(d, d);
                MicrofacetMaterial material;
                material.albedo = {parameters.at(x, y, 0), parameters.at(x, y, 1),
                                   parameters.at(x, y, 2)};
                material.roughness = parameters.at(x, y, 3);
                material.f0 = parameters.at(x, y, 4);
                const proto::Vec3d expected =
                    microfacetRadiance(material, n, proto::normalized(d),
                                       proto::normalized(proto::Vec3d{
                                           camera.x - p.x, camera.y - p.y, camera.z - p.z}));
                // The files hold floats; geometry was stored at float precision.
                EXPECT_NEAR(rendered.at(x, y, 0), irradiance * expected.x, 2e-4)
                    << image << " " << x << "," << y;
                EXPECT_NEAR(rendered.at(x, y, 2), irradiance * expected.z, 2e-4)
                    << image << " " << x << "," << y;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 27);
}

std::string slurp(const std::filesystem::path& path) {
    return text::readTextFile(path, "file");
}

TEST(Synth, IsDeterministicForASeedWhateverTheThreads) {
    testing::TemporaryFolder folder;
    SynthOptions options = smallOptions(folder / "a");
    options.noise = SynthNoise::kCamera;
    options.threads = 1;
    synthesizeCapture(options);
    options.out = folder / "b";
    options.threads = 3;
    synthesizeCapture(options);
    options.out = folder / "c";
    options.seed = 2;
    synthesizeCapture(options);
    // Byte for byte, headers included.
    for (const char* file : {"train/light000.png", "train/light201.png", "test/light010.png",
                             "truth/parameters.exr", "truth/labels.png", "train/capture.json"}) {
        EXPECT_TRUE(slurp(folder / "a" / file) == slurp(folder / "b" / file)) << file;
    }
    EXPECT_FALSE(slurp(folder / "a/train/light201.png") == slurp(folder / "c/train/light201.png"));
}

TEST(Synth, HasBothMaterialsAndShadowsWhereTheyShouldBe) {
    testing::TemporaryFolder folder;
    SynthOptions options = smallOptions(folder / "capture");
    options.size = 64;
    const SynthReport report = synthesizeCapture(options);
    EXPECT_EQ(report.trainImages, 330);
    EXPECT_EQ(report.testImages, 21);
    EXPECT_GT(report.streakFraction, 0.05);
    EXPECT_LT(report.streakFraction, 0.4);
    EXPECT_GT(report.shadowedFraction, 0.005);
    options.shadows = false;
    EXPECT_EQ(synthesizeCapture(options).shadowedFraction, 0.0);
}

TEST(Synth, FitOfAFourierTruthIsExact) {
    testing::TemporaryFolder folder;
    SynthOptions options = smallOptions(folder / "capture");
    options.reflectance = SynthReflectance::kFourier;
    options.fourierHarmonics = 4;
    options.encoding = SynthEncoding::kExr;
    options.shadows = false;  // shadows are not in any BRDF
    synthesizeCapture(options);
    fit::FitOptions fit;
    fit.harmonics = 4;
    fit.lambda = 0.0;  // exact accumulation
    fit.writePreview = false;
    fit::fitCapture(capture::openCapture(folder / "capture/train"), fit, folder / "model.exr");
    const eval::EvaluationReport report =
        eval::evaluateModel(folder / "model.exr", capture::openCapture(folder / "capture/test"),
                            eval::EvaluationOptions{});
    EXPECT_GT(report.psnr, 80.0);
    // The truth file is itself a model: evaluating it reproduces the test images exactly.
    const eval::EvaluationReport truth = eval::evaluateModel(
        folder / "capture/truth/fourier.exr", capture::openCapture(folder / "capture/test"),
        eval::EvaluationOptions{});
    EXPECT_GT(truth.psnr, 90.0);
    // The physical scale travels: manifest → fit → model; and the truth carries it too.
    const double texel = 108.38 / 24;  // 100 mm a unit, 1.0838 units across the front
    EXPECT_NEAR(*capture::openCapture(folder / "capture/train").texelMm, texel, 0.01);
    EXPECT_NEAR(model::ModelReader(folder / "model.exr").info().texelMm, texel, 0.01);
    EXPECT_NEAR(model::ModelReader(folder / "capture/truth/fourier.exr").info().texelMm, texel,
                0.01);
}

// At the smallest size, under the dome's 49 lights and without shadows: what is written does
// not matter here, only where.
TEST(Synth, RefusesToReplaceAFolderItDidNotWrite) {
    testing::TemporaryFolder folder;
    std::filesystem::create_directories(folder / "precious");
    std::ofstream(folder / "precious/notes.txt") << "keep me";
    SynthOptions options = smallOptions(folder / "precious");
    options.size = 8;
    options.rig = "dome";
    options.shadows = false;
    EXPECT_THROW(synthesizeCapture(options), common::InputError);
    EXPECT_TRUE(std::filesystem::exists(folder / "precious/notes.txt"));
    // But it does replace its own output.
    options.out = folder / "capture";
    synthesizeCapture(options);
    synthesizeCapture(options);
    EXPECT_TRUE(std::filesystem::exists(folder / "capture/truth/synth.json"));
}

}  // namespace
}  // namespace vpe::synth
