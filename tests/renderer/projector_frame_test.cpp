// SPDX-License-Identifier: MIT
// renderProjectorFrame on a plane facing the projector, where every level is known in closed
// form; clipping, the gain helper, threads.
#include "vpe/renderer/cpu/projector_frame.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/renderer/cpu/visitor_view.h"

#include "test_scenes.h"

namespace vpe::renderer {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGamma = 2.2;
constexpr double kPeak = 4.0;
constexpr double kAlbedo = 0.85;

// The projector at the origin looking along +z (R = I, T = 0) with lens distortion; the plane
// z = 1 fills its view, facing it; the light sits at the projector; material kd only.
class PlaneScene : public ::testing::Test {
protected:
    void SetUp() override { build({0.6, 0.5, 0.4}); }

    void build(const std::array<double, 3>& kd) {
        mesh_ = testing::makePlaneMesh(1.0, 1.0, 8);
        material_ = testing::makeMaterial(2, 4, 4, [kd](int, int, int k, int c) {
            return k == proto::kLambertIndex ? kd[static_cast<std::size_t>(c)] : 0.0;
        });
        scene_.mesh = mesh_.view();
        scene_.material = material_.view();
        scene_.projector.camera =
            testing::centredPinhole(160, 120, 60.0 / std::tan(15.0 * kPi / 180));
        scene_.projector.camera.distortion = {-0.1, 0.02, 0.001, -0.001, 0.0};
        scene_.projector.response = proto::ResponseFunction::gamma(kGamma);
        scene_.projector.peakIrradiance = kPeak;
        scene_.surface.albedo = {kAlbedo, kAlbedo, kAlbedo};
        scene_.light.position = {0, 0, 0};
        scene_.light.intensity = {1, 1, 1};
        scene_.viewer = {0.3, 0, 0};
        // As the texture holds them: the expected values use the same numbers.
        for (std::size_t c = 0; c < 3; ++c) {
            kd_[c] = static_cast<double>(static_cast<float>(kd[c]));
        }
    }

    // |X|² for the point pixel (x, y) sees on the plane z = 1.
    double squaredDistance(int x, int y) const {
        const proto::PinholeCamera& camera = scene_.projector.camera;
        const Vec2d ideal = undistortNormalized(camera.distortion,
                                                pixelToNormalized(camera, {double(x), double(y)}));
        return ideal.x * ideal.x + ideal.y * ideal.y + 1;
    }
    // Relative output the pixel needs (cos θd = cos θp = 1/|X|, d = |X|).
    double need(int x, int y, std::size_t c, double gain = 1.0) const {
        const double distance = std::sqrt(squaredDistance(x, y));
        const double radiance = gain * kd_[c] / distance;
        const double scale = kPeak / (distance * distance * distance);
        return (kPi * radiance / kAlbedo - scene_.surface.ambientIrradiance[c]) / scale;
    }

    testing::OwnedMesh mesh_;
    testing::OwnedMaterial material_;
    RenderScene scene_;
    std::array<double, 3> kd_{};
};

TEST_F(PlaneScene, LevelsAreTheAnalyticCompensation) {
    scene_.surface.ambientIrradiance = {0.1, 0.05, 0.0};
    const ProjectorFrame frame = renderProjectorFrame(scene_, {.gain = 1.0, .threads = 2});
    EXPECT_EQ(frame.stats.coveredPixels, 160u * 120u);
    EXPECT_EQ(frame.stats.clippedPixels, 0u);
    double worst = 0;
    for (int y = 0; y < 120; ++y) {
        for (int x = 0; x < 160; ++x) {
            for (std::size_t c = 0; c < 3; ++c) {
                const double expected = std::pow(need(x, y, c), 1 / kGamma);
                worst = std::max(
                    worst, std::abs(static_cast<double>(frame.level.pixel(x, y)[c]) - expected));
                EXPECT_NEAR(frame.targetRadiance.pixel(x, y)[c],
                            kd_[c] / std::sqrt(squaredDistance(x, y)), 1e-6);
            }
        }
    }
    EXPECT_LT(worst, 1e-6);
}

TEST_F(PlaneScene, SimulationFromTheProjectorsOwnViewpointReproducesTheTarget) {
    // A viewer camera identical to the projector: every viewer pixel samples exactly one
    // projector pixel, so no resampling — only float storage separates the two.
    scene_.surface.ambientIrradiance = {0.1, 0.05, 0.0};
    scene_.viewer = scene_.projector.camera.center();
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    const SimulatedView simulated =
        simulateVisitorView(scene_, frame.level, scene_.projector.camera);
    const DirectView direct = renderDirectView(scene_, scene_.projector.camera);
    for (std::size_t i = 0; i < direct.radiance.values.size(); ++i) {
        EXPECT_NEAR(simulated.radiance.values[i], direct.radiance.values[i],
                    2e-6 * static_cast<double>(direct.radiance.values[i]));
    }
    for (std::size_t i = 0; i < simulated.lit.values.size(); ++i) {
        EXPECT_EQ(simulated.lit.values[i], 1);
    }
}

TEST_F(PlaneScene, ViewDependentTermsFollowTheViewerAndTheLightFalloff) {
    // a0 and a1 only (M = 1), a point light with inverse-square falloff: L = I·(d_ref/|l|)²·
    // (a0/√2 + a1·cos θs), cos θs = 2(n·l)(n·v) − l·v.
    const std::array<double, 3> a0{0.2, 0.1, 0.3}, a1{0.3, 0.25, 0.1};
    material_ = testing::makeMaterial(1, 2, 2, [&](int, int, int k, int c) {
        const auto i = static_cast<std::size_t>(c);
        return k == proto::kConstantIndex ? a0[i] : (k == proto::cosineIndex(1) ? a1[i] : 0.0);
    });
    scene_.material = material_.view();
    scene_.light = {.position = {0.2, 0.1, 0.3},
                    .intensity = {1.0, 0.8, 0.6},
                    .inverseSquare = true,
                    .referenceDistance = 0.5};
    scene_.viewer = {-0.3, 0.2, -0.5};
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    const proto::PinholeCamera& camera = scene_.projector.camera;
    const Vec3d n{0, 0, -1};
    for (int y = 0; y < 120; y += 11) {
        for (int x = 0; x < 160; x += 9) {
            const Vec2d ideal = undistortNormalized(
                camera.distortion, pixelToNormalized(camera, {double(x), double(y)}));
            const Vec3d X{ideal.x, ideal.y, 1.0};
            const Vec3d toLight{0.2 - X.x, 0.1 - X.y, 0.3 - X.z};
            const Vec3d toViewer{-0.3 - X.x, 0.2 - X.y, -0.5 - X.z};
            const Vec3d l = proto::normalized(toLight), v = proto::normalized(toViewer);
            const double cosS = 2 * proto::dot(n, l) * proto::dot(n, v) - proto::dot(l, v);
            const double falloff = 0.25 / proto::dot(toLight, toLight);
            for (std::size_t c = 0; c < 3; ++c) {
                const double f = static_cast<double>(static_cast<float>(a0[c])) / std::sqrt(2.0) +
                                 static_cast<double>(static_cast<float>(a1[c])) * cosS;
                const double expected = std::max(scene_.light.intensity[c] * falloff * f, 0.0);
                EXPECT_NEAR(frame.targetRadiance.pixel(x, y)[c], expected, 1e-6 * (1 + expected))
                    << x << "," << y << " channel " << c;
            }
        }
    }
}

TEST_F(PlaneScene, ZeroCoefficientsGiveBlack) {
    build({0, 0, 0});
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    EXPECT_EQ(frame.stats.coveredPixels, 160u * 120u);
    EXPECT_EQ(frame.stats.clippedPixels, 0u);
    EXPECT_TRUE(std::all_of(frame.level.values.begin(), frame.level.values.end(),
                            [](float v) { return v == 0.0f; }));
    EXPECT_TRUE(std::all_of(frame.targetRadiance.values.begin(), frame.targetRadiance.values.end(),
                            [](float v) { return v == 0.0f; }));
    // With room light on the plaster, black is out of reach: every pixel clips at the bottom.
    scene_.surface.ambientIrradiance = {0.01, 0.01, 0.01};
    const ProjectorFrame lit = renderProjectorFrame(scene_);
    EXPECT_EQ(lit.stats.clippedLowPixels, lit.stats.coveredPixels);
    EXPECT_EQ(lit.stats.clippedHighPixels, 0u);
    EXPECT_DOUBLE_EQ(lit.stats.clippedFraction, 1.0);
}

TEST_F(PlaneScene, PixelsOffTheObjectAreBlack) {
    mesh_ = testing::makePlaneMesh(1.0, 0.1, 2);  // covers the middle only
    scene_.mesh = mesh_.view();
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    EXPECT_GT(frame.stats.coveredPixels, 0u);
    EXPECT_LT(frame.stats.coveredPixels, 160u * 120u / 4);
    EXPECT_EQ(frame.coverage.at(0, 0), 0);
    EXPECT_EQ(frame.level.pixel(0, 0)[0], 0.0f);
    EXPECT_EQ(frame.coverage.at(80, 60), 1);
    EXPECT_GT(frame.level.pixel(80, 60)[0], 0.0f);
}

TEST_F(PlaneScene, ClippedFractionCountsThePixelsThatNeedMoreThanFullOutput) {
    // Red needs full output at |X|² = 1.08: the corners of the image clip.
    build({kAlbedo * kPeak / (kPi * 1.08), 0.3, 0.2});
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    std::size_t expected = 0;
    for (int y = 0; y < 120; ++y) {
        for (int x = 0; x < 160; ++x) {
            const double red = need(x, y, 0);
            ASSERT_GT(std::abs(red - 1), 1e-9) << "a pixel on the edge of clipping: ambiguous";
            const bool clipped = red > 1;
            expected += clipped ? 1 : 0;
            EXPECT_EQ(frame.clipped.at(x, y), clipped ? kClippedHigh : 0) << x << "," << y;
            if (clipped) {
                EXPECT_EQ(frame.level.pixel(x, y)[0], 1.0f);
            }
        }
    }
    EXPECT_GT(expected, 1000u);
    EXPECT_LT(expected, 160u * 120u / 2);
    EXPECT_EQ(frame.stats.clippedHighPixels, expected);
    EXPECT_EQ(frame.stats.clippedPixels, expected);
    EXPECT_DOUBLE_EQ(frame.stats.clippedFraction, static_cast<double>(expected) / (160.0 * 120.0));
}

TEST_F(PlaneScene, GainHelperFindsTheLargestGainWithinTheClippingBudget) {
    build({kAlbedo * kPeak / (kPi * 1.08), 0.3, 0.2});
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    const std::size_t pixels = frame.stats.coveredPixels;
    for (const double budget : {0.0, 0.005, 0.1}) {
        const double gain = gainForClippedFraction(frame, budget);
        // Analytic: red decides; pixel limit = 1 / need(gain 1).
        std::vector<double> limits;
        for (int y = 0; y < 120; ++y) {
            for (int x = 0; x < 160; ++x) {
                limits.push_back(1.0 / need(x, y, 0));
            }
        }
        std::sort(limits.begin(), limits.end());
        const auto allowed = static_cast<std::size_t>(std::floor(budget * double(pixels)));
        EXPECT_NEAR(gain, std::min(1.0, limits[allowed]), 1e-6) << budget;
        const ProjectorFrame at = renderProjectorFrame(scene_, {.gain = gain});
        EXPECT_LE(at.stats.clippedHighPixels, allowed) << budget;
        const ProjectorFrame above = renderProjectorFrame(scene_, {.gain = gain * (1 + 1e-5)});
        EXPECT_GT(above.stats.clippedHighPixels, allowed) << budget;
    }
    EXPECT_EQ(gainForClippedFraction(frame, 1.0), 1.0);
    build({0.3, 0.3, 0.3});  // nothing clips at gain 1
    EXPECT_EQ(gainForClippedFraction(renderProjectorFrame(scene_), 0.0), 1.0);
}

TEST_F(PlaneScene, SampledResponseIsInverted) {
    // A curve with a black level: level = r⁻¹(need) on every pixel.
    std::vector<double> levels, outputs;
    for (int k = 0; k <= 16; ++k) {
        levels.push_back(k / 16.0);
        outputs.push_back(0.02 + std::pow(k / 16.0, 2.4));
    }
    scene_.projector.response =
        proto::ResponseFunction::sampled(levels, {outputs, outputs, outputs});
    const ProjectorFrame frame = renderProjectorFrame(scene_);
    for (int y = 0; y < 120; y += 13) {
        for (int x = 0; x < 160; x += 7) {
            for (int c = 0; c < 3; ++c) {
                const double level = frame.level.pixel(x, y)[c];
                EXPECT_NEAR(scene_.projector.response.output(c, level),
                            need(x, y, static_cast<std::size_t>(c)), 1e-6);
            }
        }
    }
}

TEST_F(PlaneScene, RefusesBadInput) {
    RenderScene bad = scene_;
    bad.surface.albedo[1] = 0;
    EXPECT_THROW(renderProjectorFrame(bad), std::invalid_argument);
    EXPECT_THROW(renderProjectorFrame(scene_, {.gain = 0}), std::invalid_argument);
    bad = scene_;
    bad.mesh.indices = bad.mesh.indices.first(4);
    EXPECT_THROW(renderProjectorFrame(bad), std::invalid_argument);
    const RgbImage wrongSize(10, 10);
    EXPECT_THROW(simulateVisitorView(scene_, wrongSize, scene_.projector.camera),
                 std::invalid_argument);
}

}  // namespace
}  // namespace vpe::renderer
