// SPDX-License-Identifier: MIT
// Weight maps and region composition: the spec and its errors, Σα = 1 for every generator,
// determinism, image weights, and the linearity that makes blending coefficients equal to
// blending renderings; `vpe compose` end to end.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/reflection_geometry.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/texture/region_compose.h"
#include "vpe/texture/weight_maps.h"

#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/test_data.h"

namespace vpe {
namespace {

using texture::WeightKind;
using texture::WeightMaps;
using texture::WeightSource;

// Coefficient k of channel c at (x, y).
using CoefficientFunction = std::function<float(int x, int y, int c, int k)>;

void writeRegionMap(const std::filesystem::path& path, int width, int height, int harmonics,
                    const CoefficientFunction& coefficient,
                    const std::function<bool(int x, int y)>& valid = {}) {
    model::ModelInfo info;
    info.width = width;
    info.height = height;
    info.harmonics = harmonics;
    info.capture = "compose test";
    model::ModelRows rows;
    const int k = proto::coefficientCount(harmonics);
    rows.resize(width, height, k);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t p = rows.pixel(y, x);
            rows.normal[p * 3 + 2] = 1.0f;
            rows.valid[p] = !valid || valid(x, y) ? 1 : 0;
            for (int c = 0; c < 3; ++c) {
                rows.rms[p * 3 + c] = 0.01f * static_cast<float>(c + 1);
                for (int i = 0; i < k; ++i) {
                    rows.coefficient[(p * 3 + c) * k + i] =
                        rows.valid[p] ? coefficient(x, y, c, i) : 0;
                }
            }
        }
    }
    model::ModelWriter writer(path, info);
    writer.writeRows(0, rows);
    writer.finish();
}

model::ModelRows readModel(const std::filesystem::path& path, model::ModelInfo* infoOut = nullptr) {
    model::ModelReader reader(path);
    model::ModelRows rows;
    reader.readRows(0, reader.info().height, rows);
    if (infoOut != nullptr) {
        *infoOut = reader.info();
    }
    return rows;
}

CoefficientFunction randomCoefficients(std::uint32_t seed) {
    return [seed](int x, int y, int c, int k) {
        std::mt19937 random(seed * 7919u +
                            static_cast<std::uint32_t>(((y * 64 + x) * 3 + c) * 64 + k));
        return std::uniform_real_distribution<float>(-1.0f, 1.0f)(random);
    };
}

std::vector<WeightSource> parse(const std::string& spec) {
    return texture::parseWeightSpec(spec);
}

// Σ_k α_k = 1 and α_k ∈ [0, 1] at every pixel, to float rounding.
void expectPartitionOfUnity(const WeightMaps& maps) {
    for (int y = 0; y < maps.height; ++y) {
        for (int x = 0; x < maps.width; ++x) {
            double sum = 0;
            for (int k = 0; k < maps.regions(); ++k) {
                const float a = maps.at(k, x, y);
                ASSERT_GE(a, 0.0f) << "region " << k << " at " << x << ", " << y;
                ASSERT_LE(a, 1.0f) << "region " << k << " at " << x << ", " << y;
                sum += a;
            }
            ASSERT_NEAR(sum, 1.0, 1e-6) << x << ", " << y;
        }
    }
}

void expectInputErrorMentioning(const std::function<void()>& call,
                                const std::vector<std::string>& mentions) {
    try {
        call();
        ADD_FAILURE() << "no InputError";
    } catch (const common::InputError& error) {
        const std::string message = error.what();
        for (const std::string& mention : mentions) {
            EXPECT_NE(message.find(mention), std::string::npos)
                << "'" << mention << "' not in: " << message;
        }
    }
}

// ---- the spec -------------------------------------------------------------------------

TEST(WeightSpec, ParsesEveryKindWithItsParameters) {
    const auto sources = parse(
        "image:paint/streaks.png:invert,stripes:angle=30:period=64:sharpness=2:phase=0.25,"
        "radial:cx=10:cy=12.5:radius=5,noise:scale=40:seed=2:octaves=3:sharpness=1.5,"
        "constant:value=0.5,stripes");
    ASSERT_EQ(sources.size(), 6u);
    EXPECT_EQ(sources[0].kind, WeightKind::kImage);
    EXPECT_EQ(sources[0].image, "paint/streaks.png");
    EXPECT_TRUE(sources[0].invert);
    EXPECT_EQ(sources[1].kind, WeightKind::kStripes);
    EXPECT_EQ(sources[1].angleDegrees, 30);
    EXPECT_EQ(sources[1].period, 64);
    EXPECT_EQ(sources[1].sharpness, 2);
    EXPECT_EQ(sources[1].phase, 0.25);
    EXPECT_FALSE(sources[1].invert);
    EXPECT_EQ(sources[2].kind, WeightKind::kRadial);
    EXPECT_EQ(sources[2].centreX, 10);
    EXPECT_EQ(sources[2].centreY, 12.5);
    EXPECT_EQ(sources[2].radius, 5);
    EXPECT_EQ(sources[3].kind, WeightKind::kNoise);
    EXPECT_EQ(sources[3].scale, 40);
    EXPECT_EQ(sources[3].seed, 2u);
    EXPECT_EQ(sources[3].octaves, 3);
    EXPECT_EQ(sources[3].sharpness, 1.5);
    EXPECT_EQ(sources[4].kind, WeightKind::kConstant);
    EXPECT_EQ(sources[4].value, 0.5);
    // Defaults.
    EXPECT_EQ(sources[5].angleDegrees, 0);
    EXPECT_EQ(sources[5].period, 64);
    EXPECT_EQ(sources[5].sharpness, 0);
    EXPECT_EQ(sources[5].index, 6);
    EXPECT_EQ(sources[5].entry, "stripes");
}

TEST(WeightSpec, ErrorsNameTheEntryAndTheProblem) {
    struct Case {
        std::string spec;
        std::vector<std::string> mentions;
    };
    const std::vector<Case> cases = {
        {"", {"--weights", "empty"}},
        {"constant,,noise", {"entry 2", "empty entry"}},
        {"constant,", {"entry 2", "empty entry"}},
        {"constant,blob:x=1", {"entry 2", "'blob:x=1'", "unknown kind 'blob'"}},
        {"stripes:angle=abc", {"entry 1", "'stripes:angle=abc'", "angle", "not a number"}},
        {"stripes:angle=30deg", {"entry 1", "angle", "not a number"}},
        {"stripes:angle=", {"entry 1", "angle", "not a number"}},
        {"stripes:period=0", {"period", "out of range"}},
        {"stripes:period=-5", {"period", "out of range"}},
        {"stripes:angle=1e400", {"angle", "not a number"}},
        {"stripes:sharpness=-1", {"sharpness", "out of range"}},
        {"stripes:colour=red", {"unknown parameter 'colour'", "accepted", "period"}},
        {"stripes:period", {"'period' is not NAME=VALUE"}},
        {"stripes:period=8:period=9", {"'period' given twice"}},
        {"radial:radius=0", {"radius", "out of range"}},
        {"noise:seed=-1", {"seed", "not a non-negative integer"}},
        {"noise:seed=1.5", {"seed", "not a non-negative integer"}},
        {"noise:octaves=9", {"octaves", "out of range"}},
        {"noise:scale=nan", {"scale", "not a number"}},
        {"constant:value=-0.1", {"value", "out of range"}},
        {"constant:invert", {"'invert' does not apply"}},
        {"noise:invert:invert", {"'invert' given twice"}},
        {"image", {"image needs a path"}},
        {"image:", {"image needs a path"}},
        {"image:a.png:gain=2", {"unknown parameter 'gain'"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.spec);
        expectInputErrorMentioning([&] { parse(c.spec); }, c.mentions);
    }
    // The option name comes from the caller.
    expectInputErrorMentioning([] { texture::parseWeightSpec("blob", "weights.txt"); },
                               {"weights.txt entry 1"});
}

// ---- the generators -------------------------------------------------------------------

TEST(WeightMaps, SumToOneForEveryGenerator) {
    const testing::TemporaryFolder folder;
    std::vector<float> grey(17 * 13);
    for (std::size_t i = 0; i < grey.size(); ++i) {
        grey[i] = static_cast<float>(i % 7) / 6.0f;
    }
    image::writeImage(folder / "grey.exr", 17, 13, 1, grey, image::PixelFormat::kFloat);
    const std::vector<std::string> specs = {
        "stripes:angle=30:period=9,stripes:angle=30:period=9:invert",
        "stripes:angle=-45:period=5:sharpness=4,radial:radius=20,noise:scale=6:seed=3",
        "radial:cx=3:cy=4:radius=8:invert,noise:scale=3:seed=9:octaves=4:sharpness=3",
        "constant:value=0.2,constant:value=3,image:" + (folder / "grey.exr").string(),
        "image:" + (folder / "grey.exr").string() + ",image:" + (folder / "grey.exr").string() +
            ":invert",
        "noise:seed=1,noise:seed=1:invert,constant:value=0",
        "strokes:width=3:coverage=0.3,strokes:width=3:coverage=0.3:invert,constant:value=0",
    };
    for (const std::string& spec : specs) {
        SCOPED_TRACE(spec);
        for (const auto& [width, height] : {std::pair{17, 13}, std::pair{40, 25}}) {
            const WeightMaps maps = texture::buildWeightMaps(parse(spec), width, height);
            EXPECT_EQ(maps.regions(), static_cast<int>(parse(spec).size()));
            expectPartitionOfUnity(maps);
        }
    }
}

TEST(WeightMaps, AllZeroPixelsGetEqualWeights) {
    // A small disc and nothing else: outside it every raw weight is 0.
    const WeightMaps maps = texture::buildWeightMaps(
        parse("radial:cx=10:cy=10:radius=4,constant:value=0,constant:value=0"), 20, 20);
    expectPartitionOfUnity(maps);
    EXPECT_EQ(maps.at(0, 10, 10), 1.0f);  // the disc's centre: all region 0
    EXPECT_EQ(maps.at(1, 10, 10), 0.0f);
    for (int k = 0; k < 3; ++k) {
        EXPECT_FLOAT_EQ(maps.at(k, 0, 0), 1.0f / 3.0f);
    }
    EXPECT_GT(maps.zeroSumPixels, 300u);
    EXPECT_LT(maps.zeroSumPixels, 400u - 40u);
}

TEST(WeightMaps, GeneratorsAreDeterministic) {
    for (const std::string spec :
         {"stripes:angle=17:period=11:sharpness=3:phase=0.3", "radial:cx=5:cy=30:radius=21",
          "noise:scale=7:seed=42:octaves=3", "noise:scale=7:seed=42:sharpness=5:invert"}) {
        SCOPED_TRACE(spec);
        const WeightSource source = parse(spec).front();
        const std::vector<float> a = texture::generateWeight(source, 33, 29);
        const std::vector<float> b = texture::generateWeight(source, 33, 29);
        EXPECT_EQ(a, b);
        // Not constant: the generator does something.
        EXPECT_NE(*std::min_element(a.begin(), a.end()), *std::max_element(a.begin(), a.end()));
    }
    const auto seed1 = texture::generateWeight(parse("noise:seed=1").front(), 64, 64);
    const auto seed2 = texture::generateWeight(parse("noise:seed=2").front(), 64, 64);
    EXPECT_NE(seed1, seed2);
}

TEST(WeightMaps, GeneratorShapes) {
    const int size = 48;
    auto value = [&](const std::vector<float>& map, int x, int y) {
        return map[static_cast<std::size_t>(y) * size + x];
    };
    // angle 0: horizontal stripes, constant along x, period 12 along y.
    const auto horizontal = texture::generateWeight(parse("stripes:period=12").front(), size, size);
    // angle 90: vertical stripes.
    const auto vertical =
        texture::generateWeight(parse("stripes:angle=90:period=12").front(), size, size);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            EXPECT_NEAR(value(horizontal, x, y), value(horizontal, 0, y), 1e-6);
            EXPECT_NEAR(value(vertical, x, y), value(vertical, x, 0), 1e-6);
            if (y + 12 < size) {
                EXPECT_NEAR(value(horizontal, x, y), value(horizontal, x, y + 12), 1e-5);
            }
            EXPECT_NEAR(value(horizontal, x, y), value(vertical, y, x), 1e-6);
        }
    }
    // A sharp wave is nearly a square wave: mostly near 0 or 1.
    const auto sharp =
        texture::generateWeight(parse("stripes:period=12:sharpness=20").front(), size, size);
    int extreme = 0;
    for (float v : sharp) {
        extreme += v < 0.05f || v > 0.95f ? 1 : 0;
    }
    EXPECT_GT(extreme, size * size * 3 / 4);
    // Radial: 1 at the centre, linear falloff, 0 beyond the radius.
    const auto radial =
        texture::generateWeight(parse("radial:cx=24:cy=24:radius=10").front(), size, size);
    EXPECT_NEAR(value(radial, 23, 23), 1 - std::sqrt(0.5) / 10, 1e-6);  // pixel centre 23.5
    EXPECT_NEAR(value(radial, 28, 23), 1 - std::hypot(4.5, 0.5) / 10, 1e-6);
    EXPECT_EQ(value(radial, 0, 0), 0.0f);
    EXPECT_EQ(value(radial, 40, 24), 0.0f);
    // invert is 1 − value.
    const auto inverted =
        texture::generateWeight(parse("radial:cx=24:cy=24:radius=10:invert").front(), size, size);
    for (std::size_t i = 0; i < radial.size(); ++i) {
        EXPECT_NEAR(radial[i] + inverted[i], 1.0f, 1e-6);
    }
    // constant
    for (float v : texture::generateWeight(parse("constant:value=0.75").front(), 5, 5)) {
        EXPECT_EQ(v, 0.75f);
    }
    // Noise stays in [0, 1] and varies on its scale.
    const auto noise = texture::generateWeight(parse("noise:scale=8:seed=5").front(), size, size);
    for (float v : noise) {
        EXPECT_GE(v, 0.0f);
        EXPECT_LE(v, 1.0f);
    }
}

TEST(WeightMaps, ImagesAreReadAsGreyAndResizedBilinearly) {
    const testing::TemporaryFolder folder;
    // 2 × 2 checker, float: [0 1; 1 0].
    image::writeImage(folder / "checker.exr", 2, 2, 1, {0, 1, 1, 0}, image::PixelFormat::kFloat);
    const WeightSource checker = parse("image:" + (folder / "checker.exr").string()).front();
    EXPECT_EQ(texture::generateWeight(checker, 2, 2), (std::vector<float>{0, 1, 1, 0}));
    // To 4 × 4 with pixel centres aligned: output x = 1 samples source x = 0.25.
    const std::vector<float> big = texture::generateWeight(checker, 4, 4);
    EXPECT_FLOAT_EQ(big[0], 0.0f);                       // (0, 0): clamped to source (0, 0)
    EXPECT_FLOAT_EQ(big[1], 0.25f);                      // (1, 0)
    EXPECT_FLOAT_EQ(big[2], 0.75f);                      // (2, 0)
    EXPECT_FLOAT_EQ(big[3], 1.0f);                       // (3, 0)
    EXPECT_FLOAT_EQ(big[1 * 4 + 1], 0.25f * 0.75f * 2);  // (1, 1): 0.75·0.25 + 0.25·0.75
    // Down to 1 × 1: the centre, the mean here.
    EXPECT_FLOAT_EQ(texture::generateWeight(checker, 1, 1)[0], 0.5f);
    // RGB: Rec. 709 luma of the stored values; 8-bit values scaled to [0, 1].
    image::writeImage8(folder / "rgb.png", 1, 1, 3, {255, 0, 0});
    EXPECT_NEAR(
        texture::generateWeight(parse("image:" + (folder / "rgb.png").string()).front(), 1, 1)[0],
        0.2126, 1e-6);
    image::writeImage8(folder / "grey.png", 1, 1, 1, {51});
    EXPECT_NEAR(texture::generateWeight(
                    parse("image:" + (folder / "grey.png").string() + ":invert").front(), 1, 1)[0],
                0.8, 1e-6);
}

TEST(WeightMaps, BadImagesNameTheFileAndPixel) {
    const testing::TemporaryFolder folder;
    image::writeImage(folder / "negative.exr", 3, 2, 1, {0, 0, 0, 0, -0.5f, 0},
                      image::PixelFormat::kFloat);
    expectInputErrorMentioning(
        [&] {
            texture::generateWeight(parse("image:" + (folder / "negative.exr").string()).front(), 3,
                                    2);
        },
        {"negative.exr", "pixel (1, 1)", "≥ 0"});
    expectInputErrorMentioning(
        [&] {
            texture::generateWeight(parse("image:" + (folder / "missing.png").string()).front(), 3,
                                    2);
        },
        {"missing.png"});
}

// ---- composition ----------------------------------------------------------------------

// The blend of coefficients renders exactly as the blend of the regions' renderings: the
// model is linear in its coefficients (paper eq. 20 applied to coefficients).
TEST(Compose, BlendedCoefficientsRenderAsBlendedRenderings) {
    const testing::TemporaryFolder folder;
    const int width = 14, height = 11, harmonics = 4, regions = 3;
    for (int k = 0; k < regions; ++k) {
        writeRegionMap(quilt::regionMapPath(folder.path(), k), width, height, harmonics,
                       randomCoefficients(static_cast<std::uint32_t>(k + 1)));
    }
    const auto maps = quilt::listRegionMaps(folder.path());
    ASSERT_EQ(maps.size(), 3u);
    const WeightMaps weights = texture::buildWeightMaps(
        parse("stripes:angle=30:period=7:sharpness=2,radial:radius=6,noise:scale=4:seed=3"), width,
        height);
    const texture::ComposeReport report =
        texture::composeRegionMaps(maps, weights, folder / "composed.exr");
    EXPECT_EQ(report.regions, 3);
    EXPECT_EQ(report.harmonics, harmonics);
    EXPECT_EQ(report.invalidPixels, 0u);
    double meanSum = 0;
    for (double mean : report.meanWeight) {
        meanSum += mean;
    }
    EXPECT_NEAR(meanSum, 1.0, 1e-6);  // each α is rounded to float

    model::ModelInfo info;
    const model::ModelRows composed = readModel(folder / "composed.exr", &info);
    EXPECT_EQ(info.width, width);
    EXPECT_EQ(info.height, height);
    EXPECT_EQ(info.harmonics, harmonics);
    EXPECT_EQ(info.variant, "paper");
    std::vector<model::ModelRows> inputs;
    for (const auto& map : maps) {
        inputs.push_back(readModel(map));
    }

    using V = proto::Vec3<double>;
    struct Configuration {
        V normal, light, view;
    };
    const std::vector<Configuration> configurations = {
        {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}},                        // head-on
        {{0, 0, 1}, {0.6, 0, 0.8}, {0, 0, 1}},                    // light 37° off
        {{0, 0, 1}, {-0.6, 0, 0.8}, {0.6, 0, 0.8}},               // near the mirror direction
        {{0.3, -0.2, 0.93}, {0.1, 0.7, 0.7}, {-0.4, 0.1, 0.9}},   // tilted normal
        {{0, 0, 1}, {0.9, 0.1, -0.42}, {0, 0, 1}},                // light below the horizon
        {{0.7, 0, 0.71}, {-0.2, -0.5, 0.84}, {0.5, 0.5, 0.707}},  // grazing
    };
    const int k = proto::coefficientCount(harmonics);
    double largest = 0;
    for (const Configuration& configuration : configurations) {
        const auto angles = proto::reflectionAngles(proto::normalized(configuration.normal),
                                                    proto::normalized(configuration.light),
                                                    proto::normalized(configuration.view));
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t p = composed.pixel(y, x);
                ASSERT_TRUE(composed.valid[p]);
                EXPECT_EQ(composed.normal[p * 3 + 0], 0.0f);
                EXPECT_EQ(composed.normal[p * 3 + 1], 0.0f);
                EXPECT_EQ(composed.normal[p * 3 + 2], 1.0f);
                for (int c = 0; c < 3; ++c) {
                    const double rendered = proto::evaluateFourierBrdf<double>(
                        composed.coefficientsAt(y, x, c), harmonics, angles.cosThetaD,
                        angles.cosThetaS);
                    double blended = 0, scale = 0;
                    for (int r = 0; r < regions; ++r) {
                        const double alpha = static_cast<double>(weights.at(r, x, y));
                        const double region = proto::evaluateFourierBrdf<double>(
                            inputs[static_cast<std::size_t>(r)].coefficientsAt(y, x, c), harmonics,
                            angles.cosThetaD, angles.cosThetaS);
                        blended += alpha * region;
                        for (int i = 0; i < k; ++i) {
                            scale += alpha *
                                     std::fabs(inputs[static_cast<std::size_t>(r)].coefficientsAt(
                                         y, x, c)[i]);
                        }
                    }
                    // Each composed coefficient is the exact blend rounded once to float.
                    const double tolerance = scale * 0x1.0p-23;
                    EXPECT_NEAR(rendered, blended, tolerance) << x << ", " << y << ", " << c;
                    largest = std::max(largest, std::fabs(rendered - blended));
                }
            }
        }
    }
    EXPECT_LT(largest, 2e-6);
}

TEST(Compose, RmsIsTheBlendOfRmsAndInvalidPixelsStayInvalidWhereWeighted) {
    const testing::TemporaryFolder folder;
    const int width = 6, height = 4;
    writeRegionMap(quilt::regionMapPath(folder.path(), 0), width, height, 1,
                   [](int, int, int, int) { return 1.0f; });
    // Region 1 has a hole at x = 0.
    writeRegionMap(
        quilt::regionMapPath(folder.path(), 1), width, height, 1,
        [](int, int, int, int) { return 3.0f; }, [](int x, int) { return x != 0; });
    // Region 1 weighs nothing at y = 0, half elsewhere.
    const std::filesystem::path mask = folder / "mask.exr";
    std::vector<float> pixels(static_cast<std::size_t>(width) * height, 1.0f);
    std::fill(pixels.begin(), pixels.begin() + width, 0.0f);
    image::writeImage(mask, width, height, 1, pixels, image::PixelFormat::kFloat);
    const WeightMaps weights =
        texture::buildWeightMaps(parse("constant,image:" + mask.string()), width, height);
    const auto report = texture::composeRegionMaps(quilt::listRegionMaps(folder.path()), weights,
                                                   folder / "composed.exr");
    EXPECT_EQ(report.invalidPixels, static_cast<std::size_t>(height - 1));
    const model::ModelRows composed = readModel(folder / "composed.exr");
    EXPECT_TRUE(composed.valid[composed.pixel(0, 0)]);  // α₁ = 0 there: the hole is unused
    EXPECT_EQ(composed.coefficientsAt(0, 0, 0)[0], 1.0f);
    EXPECT_FALSE(composed.valid[composed.pixel(1, 0)]);
    EXPECT_EQ(composed.coefficientsAt(1, 0, 0)[0], 0.0f);  // invalid pixels hold zeros
    EXPECT_TRUE(composed.valid[composed.pixel(1, 1)]);
    EXPECT_EQ(composed.coefficientsAt(1, 1, 2)[1], 2.0f);
    EXPECT_FLOAT_EQ(composed.rms[composed.pixel(1, 1) * 3 + 2], 0.03f);
}

TEST(Compose, MismatchedRegionMapsAreRefusedByName) {
    const testing::TemporaryFolder folder;
    auto one = [](int, int, int, int) { return 1.0f; };
    writeRegionMap(folder / "size" / "region0.exr", 6, 4, 2, one);
    writeRegionMap(folder / "size" / "region1.exr", 6, 5, 2, one);
    expectInputErrorMentioning(
        [&] { texture::checkRegionMaps(quilt::listRegionMaps(folder / "size")); },
        {"region1.exr", "6 × 5", "6 × 4"});
    writeRegionMap(folder / "harmonics" / "region0.exr", 6, 4, 2, one);
    writeRegionMap(folder / "harmonics" / "region1.exr", 6, 4, 3, one);
    expectInputErrorMentioning(
        [&] { texture::checkRegionMaps(quilt::listRegionMaps(folder / "harmonics")); },
        {"region1.exr", "3 harmonics", "has 2"});
    writeRegionMap(folder / "gap" / "region0.exr", 6, 4, 2, one);
    writeRegionMap(folder / "gap" / "region2.exr", 6, 4, 2, one);
    expectInputErrorMentioning([&] { quilt::listRegionMaps(folder / "gap"); },
                               {"region1.exr", "missing"});
    std::filesystem::create_directories(folder / "empty");
    expectInputErrorMentioning([&] { quilt::listRegionMaps(folder / "empty"); },
                               {"empty", "no region0.exr"});
}

// ---- vpe compose ----------------------------------------------------------------------

constexpr auto& vpe = testing::vpeCommand;

using testing::lastJsonLine;

TEST(ComposeCli, BlendsTwoHandMadeRegionMaps) {
    const testing::TemporaryFolder folder;
    const int width = 8, height = 6;
    // Region 0 is all 1, region 1 all 0: the composite is α₀ itself, in every coefficient.
    writeRegionMap(folder / "quilt" / "region0.exr", width, height, 2,
                   [](int, int, int, int) { return 1.0f; });
    writeRegionMap(folder / "quilt" / "region1.exr", width, height, 2,
                   [](int, int, int, int) { return 0.0f; });
    const std::string spec = "stripes:period=4,stripes:period=4:invert";
    const testing::CommandResult result = testing::runCommand(
        vpe({"compose", (folder / "quilt").string(), "--out", (folder / "composed.exr").string(),
             "--weights", spec, "--weights-out", (folder / "weights.png").string(), "--json"}));
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    const nlohmann::json json = lastJsonLine(result.out);
    EXPECT_EQ(json["regions"], 2);
    EXPECT_EQ(json["width"], width);
    EXPECT_EQ(json["height"], height);
    EXPECT_EQ(json["harmonics"], 2);
    EXPECT_EQ(json["weights"][1]["entry"], "stripes:period=4:invert");
    EXPECT_NEAR(json["weights"][0]["mean"].get<double>() + json["weights"][1]["mean"].get<double>(),
                1.0, 1e-6);
    EXPECT_EQ(json["zero_weight_pixels"], 0);
    EXPECT_EQ(json["weights_picture"], (folder / "weights.png").string());

    const WeightMaps weights = texture::buildWeightMaps(parse(spec), width, height);
    const model::ModelRows composed = readModel(folder / "composed.exr");
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c) {
                for (int i = 0; i < 6; ++i) {
                    EXPECT_FLOAT_EQ(composed.coefficientsAt(y, x, c)[i], weights.at(0, x, y));
                }
            }
        }
    }
    // Two grey tiles and a colour tile, 4 pixels apart.
    const image::FloatImage picture = image::readImage(folder / "weights.png");
    EXPECT_EQ(picture.width, 3 * width + 2 * 4);
    EXPECT_EQ(picture.height, height);
    EXPECT_EQ(picture.channels, 3);
    EXPECT_NEAR(picture.at(1, 1, 0), weights.at(0, 1, 1), 1.0 / 255);
    EXPECT_NEAR(picture.at(width + 4 + 1, 1, 0), weights.at(1, 1, 1), 1.0 / 255);
}

TEST(ComposeCli, BadInputExitsTwoNamingIt) {
    const testing::TemporaryFolder folder;
    auto one = [](int, int, int, int) { return 1.0f; };
    writeRegionMap(folder / "quilt" / "region0.exr", 8, 6, 2, one);
    writeRegionMap(folder / "quilt" / "region1.exr", 8, 6, 2, one);
    const std::string dir = (folder / "quilt").string();
    const std::string out = (folder / "out" / "composed.exr").string();
    testing::expectInputError(
        testing::runCommand(vpe({"compose", dir, "--out", out, "--weights", "constant"})),
        {"--weights has 1 entry but", "2 region maps"});
    testing::expectInputError(testing::runCommand(vpe({"compose", dir, "--out", out, "--weights",
                                                       "constant,stripes:period=x"})),
                              {"entry 2", "stripes:period=x", "not a number"});
    testing::expectInputError(
        testing::runCommand(vpe({"compose", dir, "--out", out, "--weights",
                                 "constant,image:" + (folder / "nope.png").string()})),
        {"nope.png"});
    testing::expectInputError(testing::runCommand(vpe({"compose", (folder / "none").string(),
                                                       "--out", out, "--weights", "constant"})),
                              {"none", "no such folder"});
    writeRegionMap(folder / "quilt" / "region2.exr", 8, 6, 3, one);
    testing::expectInputError(testing::runCommand(vpe({"compose", dir, "--out", out, "--weights",
                                                       "constant,constant,constant"})),
                              {"region2.exr", "3 harmonics"});
    EXPECT_FALSE(std::filesystem::exists(folder / "out" / "composed.exr"));
}

}  // namespace
}  // namespace vpe
