// SPDX-License-Identifier: MIT
// Normals: robust photometric stereo against known and real truth; normal map encodings.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Dense>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "vpe/capture/capture_loader.h"
#include "vpe/normals/normal_map.h"
#include "vpe/normals/photometric_stereo.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/luminance.h"

#include "support/synthetic_capture.h"
#include "support/test_data.h"

namespace vpe {
namespace {

constexpr double kDegrees = 180.0 / M_PI;

unsigned allThreads() {
    return std::max(1u, std::thread::hardware_concurrency());
}

// A Lambertian surface (kd only, a0 = 0) whose normals tilt up to ~35° in all directions,
// under an RTI dome with rings at 10..90° elevation: low lights fall below some pixels'
// horizons, as on real objects.
testing::SyntheticCaptureSpec lambertianSpec() {
    testing::SyntheticCaptureSpec spec;
    spec.width = 24;
    spec.height = 16;
    spec.harmonics = 0;
    spec.lights = testing::domeLights({10, 30, 50, 70, 90}, 12, 7);
    spec.normal = [](int x, int y) {
        return proto::Vec3d{0.7 * std::sin(0.4 * x), 0.6 * std::cos(0.5 * y + 0.3), 1.0};
    };
    spec.coefficients = [](int x, int y, int c, double* coefficients) {
        coefficients[proto::kLambertIndex] = 0.25 + 0.15 * c + 0.01 * x + 0.005 * y;
        coefficients[proto::kConstantIndex] = 0.0;
    };
    return spec;
}

normals::PhotometricStereoOptions stereoOptions() {
    normals::PhotometricStereoOptions options;
    options.threads = allThreads();
    return options;
}

TEST(PhotometricStereo, RecoversLambertianNormals) {
    testing::TemporaryFolder folder;
    const testing::SyntheticCaptureSpec spec = lambertianSpec();
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "capture", spec);
    const normals::NormalMap estimate =
        normals::estimateNormals(capture::openCapture(folder / "capture"), stereoOptions());
    const normals::AngularError error = normals::compareNormalMaps(
        estimate, testing::trueNormalMap(truth, spec.width, spec.height));
    EXPECT_EQ(error.pixels, static_cast<std::size_t>(spec.width * spec.height));
    EXPECT_LT(error.meanDegrees, 0.5);
}

// Each pixel's estimate is its own: estimated on some pixels alone (the held-out search's
// grid), a normal is the one the whole map holds, and no other pixel gets one.
TEST(PhotometricStereo, EstimatesChosenPixelsAsTheWholeMapDoes) {
    testing::TemporaryFolder folder;
    const testing::SyntheticCaptureSpec spec = lambertianSpec();
    writeSyntheticCapture(folder / "capture", spec);
    const capture::Capture capture = capture::openCapture(folder / "capture");
    const normals::NormalMap whole = normals::estimateNormals(capture, stereoOptions());
    std::vector<std::uint8_t> chosen(static_cast<std::size_t>(spec.width) * spec.height, 0);
    for (std::size_t p = 0; p < chosen.size(); p += 7) {
        chosen[p] = 1;
    }
    normals::PhotometricStereoOptions options = stereoOptions();
    options.pixels = &chosen;
    const normals::NormalMap some = normals::estimateNormals(capture, options);
    std::size_t compared = 0;
    for (std::size_t p = 0; p < chosen.size(); ++p) {
        ASSERT_EQ(some.valid[p], chosen[p] ? whole.valid[p] : 0) << "pixel " << p;
        if (some.valid[p]) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(some.xyz[p * 3 + c], whole.xyz[p * 3 + c]) << "pixel " << p;
            }
            ++compared;
        }
    }
    EXPECT_EQ(compared, (chosen.size() + 6) / 7);
}

double luminance(const float* rgb) {
    return vpe::proto::luminance709(rgb[0], rgb[1], rgb[2]);
}

// Pixel (x, y) sees the lights low in its own azimuth sector blocked, as a neighbouring
// bump would block them: 2 to 3 lights of each of the two lowest rings.
bool castShadow(int x, int y, const proto::Vec3d& light) {
    if (light.z > std::sin(35.0 / kDegrees)) {
        return false;
    }
    const double sector = (37.0 * x + 61.0 * y) / kDegrees;
    const double azimuth = std::atan2(light.y, light.x);
    return std::cos(azimuth - sector) > std::cos(50.0 / kDegrees);
}

TEST(PhotometricStereo, IsRobustToHighlightsAndCastShadows) {
    testing::TemporaryFolder folder;
    const testing::SyntheticCaptureSpec spec = lambertianSpec();
    const testing::SyntheticCapture truth = writeSyntheticCapture(folder / "capture", spec);
    const std::size_t pixels = static_cast<std::size_t>(spec.width) * spec.height;
    const std::size_t images = spec.lights.size();
    // Rewrite every rendered image with a sharp white highlight around the mirror direction
    // and the cast shadows, and keep each pixel's luminance for the baseline below.
    std::vector<double> observed(pixels * images);
    std::size_t shadowed = 0, highlighted = 0;
    for (std::size_t s = 0; s < images; ++s) {
        const std::filesystem::path path =
            folder / "capture" / ("light" + std::to_string(s) + ".exr");
        auto input = OIIO::ImageInput::open(path.string());
        ASSERT_TRUE(input);
        std::vector<float> rgb(pixels * 3);
        ASSERT_TRUE(input->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.data()));
        input->close();
        for (int y = 0; y < spec.height; ++y) {
            for (int x = 0; x < spec.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * spec.width + x;
                const auto angles = proto::reflectionAngles(truth.normals[p], spec.lights[s],
                                                            proto::Vec3d{0, 0, 1});
                const double highlight = angles.cosThetaD > 0
                                             ? 1.5 * std::pow(std::max(angles.cosThetaS, 0.0), 60)
                                             : 0.0;
                highlighted += highlight > 0.05 ? 1 : 0;
                const bool shadow = castShadow(x, y, spec.lights[s]);
                shadowed += shadow ? 1 : 0;
                for (int c = 0; c < 3; ++c) {
                    float& v = rgb[p * 3 + static_cast<std::size_t>(c)];
                    v = shadow ? 0.0f : v + static_cast<float>(highlight);
                }
                observed[p * images + s] = luminance(&rgb[p * 3]);
            }
        }
        auto output = OIIO::ImageOutput::create(path.string());
        ASSERT_TRUE(output &&
                    output->open(path.string(), OIIO::ImageSpec(spec.width, spec.height, 3,
                                                                OIIO::TypeDesc::FLOAT)) &&
                    output->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) && output->close());
    }
    // The perturbation is substantial: ~10% of samples shadowed, some highlights per pixel.
    EXPECT_GT(shadowed, pixels * images / 15);
    EXPECT_GT(highlighted, pixels / 2);

    const normals::NormalMap truthMap = testing::trueNormalMap(truth, spec.width, spec.height);
    const normals::AngularError robust = normals::compareNormalMaps(
        normals::estimateNormals(capture::openCapture(folder / "capture"), stereoOptions()),
        truthMap);

    // Baseline: plain least squares on every sample, as textbook photometric stereo does.
    normals::NormalMap plain;
    plain.resize(spec.width, spec.height);
    for (std::size_t p = 0; p < pixels; ++p) {
        Eigen::MatrixXd lights(images, 3);
        Eigen::VectorXd values(images);
        for (std::size_t s = 0; s < images; ++s) {
            lights.row(static_cast<Eigen::Index>(s)) << spec.lights[s].x, spec.lights[s].y,
                spec.lights[s].z;
            values[static_cast<Eigen::Index>(s)] = observed[p * images + s];
        }
        const Eigen::Vector3d g = lights.colPivHouseholderQr().solve(values).normalized();
        for (int c = 0; c < 3; ++c) {
            plain.xyz[p * 3 + static_cast<std::size_t>(c)] = static_cast<float>(g[c]);
        }
        plain.valid[p] = 1;
    }
    const normals::AngularError baseline = normals::compareNormalMaps(plain, truthMap);
    std::cout << "robust photometric stereo: mean " << robust.meanDegrees << "°, median "
              << robust.medianDegrees << "°; plain least squares: mean " << baseline.meanDegrees
              << "°, median " << baseline.medianDegrees << "°\n";
    EXPECT_EQ(robust.pixels, pixels);
    EXPECT_LT(robust.meanDegrees, 2.0);
    // The robustness is what makes the difference.
    EXPECT_GT(baseline.meanDegrees, 3.0 * robust.meanDegrees);
    EXPECT_GT(baseline.meanDegrees, 2.0);
}

// Normals for the encoding tests, with pixel (0, 0) left black as a background.
constexpr int kMapWidth = 5;
constexpr int kMapHeight = 4;

proto::Vec3d mapNormal(int x, int y) {
    return proto::normalized(proto::Vec3d{0.3 * (x - 2), -0.25 * (y - 1.5), 1.0 - 0.1 * x});
}

void writeMap(const std::filesystem::path& path, OIIO::TypeDesc type, bool offset) {
    std::vector<float> pixels;
    for (int y = 0; y < kMapHeight; ++y) {
        for (int x = 0; x < kMapWidth; ++x) {
            const proto::Vec3d n = mapNormal(x, y);
            for (double v : {n.x, n.y, n.z}) {
                const double stored = offset ? (v + 1.0) * 0.5 : v;
                pixels.push_back(x == 0 && y == 0 ? 0.0f : static_cast<float>(stored));
            }
        }
    }
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), OIIO::ImageSpec(kMapWidth, kMapHeight, 3, type)) &&
                out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
}

// Largest angle between the map and mapNormal(), over valid pixels, and the black pixel's
// validity.
void expectMap(const normals::NormalMap& map, double maxDegrees) {
    ASSERT_EQ(map.width, kMapWidth);
    ASSERT_EQ(map.height, kMapHeight);
    EXPECT_FALSE(map.valid[map.index(0, 0)]) << "black background must be invalid";
    double worst = 0;
    for (int y = 0; y < kMapHeight; ++y) {
        for (int x = 0; x < kMapWidth; ++x) {
            if (x == 0 && y == 0) {
                continue;
            }
            const std::size_t i = map.index(x, y);
            ASSERT_TRUE(map.valid[i]) << x << "," << y;
            const proto::Vec3d n = mapNormal(x, y);
            const Eigen::Vector3d a(map.xyz[i * 3], map.xyz[i * 3 + 1], map.xyz[i * 3 + 2]);
            EXPECT_NEAR(a.norm(), 1.0, 1e-6);
            // atan2 of cross and dot stays accurate for tiny angles, unlike acos.
            const Eigen::Vector3d b(n.x, n.y, n.z);
            worst = std::max(worst, std::atan2(a.cross(b).norm(), a.dot(b)) * kDegrees);
        }
    }
    EXPECT_LT(worst, maxDegrees);
}

TEST(NormalMapFile, EightBitOffsetEncoding) {
    testing::TemporaryFolder folder;
    writeMap(folder / "n8.png", OIIO::TypeDesc::UINT8, true);
    // Half a code per component: at most ~0.4° off.
    expectMap(normals::readNormalMap(folder / "n8.png", capture::NormalEncoding::kAuto), 0.5);
    expectMap(normals::readNormalMap(folder / "n8.png", capture::NormalEncoding::kOffsetRgb), 0.5);
}

TEST(NormalMapFile, SixteenBitOffsetEncoding) {
    testing::TemporaryFolder folder;
    writeMap(folder / "n16.png", OIIO::TypeDesc::UINT16, true);
    expectMap(normals::readNormalMap(folder / "n16.png", capture::NormalEncoding::kAuto), 0.005);
}

TEST(NormalMapFile, FloatRawEncoding) {
    testing::TemporaryFolder folder;
    writeMap(folder / "raw.exr", OIIO::TypeDesc::FLOAT, false);
    expectMap(normals::readNormalMap(folder / "raw.exr", capture::NormalEncoding::kAuto), 1e-4);
    expectMap(normals::readNormalMap(folder / "raw.exr", capture::NormalEncoding::kRaw), 1e-4);
}

TEST(NormalMapFile, FloatOffsetEncodingWhenAskedFor) {
    testing::TemporaryFolder folder;
    writeMap(folder / "offset.exr", OIIO::TypeDesc::FLOAT, true);
    expectMap(normals::readNormalMap(folder / "offset.exr", capture::NormalEncoding::kOffsetRgb),
              1e-4);
}

// SynthRTI sets: the dome's images against the rendered normals.png beside them.
normals::AngularError stereoOnSynthRti(const std::filesystem::path& dome) {
    const capture::Capture capture = capture::openCapture(dome);
    EXPECT_TRUE(capture.normalMap.has_value()) << dome;
    if (!capture.normalMap) {
        return {};
    }
    const normals::NormalMap truth =
        normals::readNormalMap(*capture.normalMap, capture.normalEncoding);
    const normals::NormalMap estimate = normals::estimateNormals(capture, stereoOptions());
    return normals::compareNormalMaps(estimate, truth);
}

void reportAngularError(const std::string& name, const normals::AngularError& error) {
    std::cout << name << ": mean angular error " << error.meanDegrees << "°, median "
              << error.medianDegrees << "° over " << error.pixels << " pixels\n";
}

TEST(PhotometricStereoRealData, SynthRtiSingleObject1Material1) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path dome = data / "synthrti/Single/Object1/material1/Dome";
    if (!std::filesystem::exists(dome)) {
        GTEST_SKIP() << dome << " not found";
    }
    const normals::AngularError error = stereoOnSynthRti(dome);
    reportAngularError("SynthRTI Single/Object1/material1", error);
    // Measured 0.36° mean, 0.31° median (one material, nearly Lambertian); bounds ~1.5×.
    EXPECT_EQ(error.pixels, 320u * 320u);
    EXPECT_LT(error.meanDegrees, 0.55);
    EXPECT_LT(error.medianDegrees, 0.47);
}

TEST(PhotometricStereoRealData, SynthRtiMultiObject1Material1) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path dome = data / "synthrti/Multi/Object1/material1/Dome";
    if (!std::filesystem::exists(dome)) {
        GTEST_SKIP() << dome << " not found";
    }
    const normals::AngularError error = stereoOnSynthRti(dome);
    reportAngularError("SynthRTI Multi/Object1/material1", error);
    // Measured 5.68° mean, 2.62° median: some of the materials are far from Lambertian.
    // Bounds ~1.5×.
    EXPECT_EQ(error.pixels, 320u * 320u);
    EXPECT_LT(error.meanDegrees, 8.5);
    EXPECT_LT(error.medianDegrees, 3.9);
}

TEST(PhotometricStereoRealData, LoewenkopfNormalsFaceTheCamera) {
    VPE_REQUIRE_REAL_DATA(data);
    const std::filesystem::path dir = data / "loewenkopf";
    if (!std::filesystem::exists(dir)) {
        GTEST_SKIP() << dir << " not found";
    }
    const normals::NormalMap normals =
        normals::estimateNormals(capture::openCapture(dir), stereoOptions());
    std::size_t valid = 0, facing = 0;
    double zSum = 0;
    for (std::size_t i = 0; i < normals.valid.size(); ++i) {
        if (!normals.valid[i]) {
            continue;
        }
        ++valid;
        const double z = normals.xyz[i * 3 + 2];
        zSum += z;
        facing += z > 0.5 ? 1 : 0;
    }
    const double validFraction = static_cast<double>(valid) / normals.valid.size();
    const double facingFraction = valid ? static_cast<double>(facing) / valid : 0.0;
    std::cout << "loewenkopf: " << valid << " of " << normals.valid.size()
              << " pixels valid, mean n_z " << (valid ? zSum / valid : 0.0) << ", "
              << 100.0 * facingFraction << "% with n_z > 0.5\n";
    EXPECT_EQ(normals.width, 64);
    EXPECT_EQ(normals.height, 43);
    // Measured: every pixel valid, mean n_z 0.83, 92% with n_z > 0.5 (a relief seen from
    // the front, with steep flanks).
    EXPECT_GT(validFraction, 0.99);
    EXPECT_GT(facingFraction, 0.85);
    EXPECT_GT(zSum / static_cast<double>(std::max<std::size_t>(valid, 1)), 0.75);
}

}  // namespace
}  // namespace vpe
