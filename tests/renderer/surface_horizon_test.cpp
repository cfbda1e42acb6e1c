// SPDX-License-Identifier: MIT
// The horizon (proto/surface_horizon.h) in the CPU reference: no radiance from a light below
// the surface, none toward a viewer below it, and a shading normal leaning over the geometric
// horizon does not leak light onto the dark side. Each case gave light before the horizon was
// defined (only the Lambert term clamped), because the material here has harmonics only.
#include "vpe/proto/surface_horizon.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"

#include "test_scenes.h"

namespace vpe::renderer {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A plane z = 1 facing a projector at the origin (normal (0, 0, −1)); the material is a0 and
// a1 only: bright at every angle, with no Lambert term to clamp.
class HorizonScene : public ::testing::Test {
protected:
    void SetUp() override {
        mesh_ = testing::makePlaneMesh(1.0, 0.5, 4);
        material_ = testing::makeMaterial(1, 2, 2, [](int, int, int k, int) {
            return k == proto::kConstantIndex ? 0.6 : (k == proto::cosineIndex(1) ? 0.2 : 0.0);
        });
        scene_.mesh = mesh_.view();
        scene_.material = material_.view();
        scene_.projector.camera =
            testing::centredPinhole(64, 48, 32.0 / std::tan(20.0 * kPi / 180));
        scene_.projector.response = proto::ResponseFunction::gamma(2.2);
        scene_.projector.peakIrradiance = 4.0;
        scene_.surface.albedo = {0.85, 0.85, 0.85};
        scene_.viewer = {0.1, 0.1, 0.0};  // in front
    }

    // brightest() with the light moved to `position`.
    double brightestLitFrom(const Vec3d& position) {
        scene_.light.position = position;
        return brightest();
    }

    // The largest target radiance of any covered pixel.
    double brightest() const {
        const ProjectorFrame frame = renderProjectorFrame(scene_, {.gain = 1.0, .threads = 2});
        EXPECT_EQ(frame.stats.coveredPixels, 64u * 48u);
        return *std::max_element(frame.targetRadiance.values.begin(),
                                 frame.targetRadiance.values.end());
    }

    testing::OwnedMesh mesh_;
    testing::OwnedMaterial material_;
    RenderScene scene_;
};

TEST(HorizonFactor, IsZeroBelowOneAboveAndSmoothBetween) {
    EXPECT_EQ(proto::horizonFactor(-0.5), 0.0);
    EXPECT_EQ(proto::horizonFactor(0.0), 0.0);
    EXPECT_EQ(proto::horizonFactor(proto::kHorizonWidth), 1.0);
    EXPECT_EQ(proto::horizonFactor(0.7), 1.0);
    EXPECT_DOUBLE_EQ(proto::horizonFactor(proto::kHorizonWidth / 2), 0.5);
    // C¹ at both ends: the slope vanishes there, so the terminator has no visible edge.
    const double h = 1e-7 * proto::kHorizonWidth;
    EXPECT_NEAR(proto::horizonFactor(h) / h, 0.0, 1e-5);
    EXPECT_NEAR((1.0 - proto::horizonFactor(proto::kHorizonWidth - h)) / h, 0.0, 1e-5);
    double previous = 0;
    for (int i = 0; i <= 100; ++i) {
        const double value = proto::horizonFactor(proto::kHorizonWidth * i / 100.0);
        EXPECT_GE(value, previous);
        previous = value;
    }
    EXPECT_EQ(proto::horizonFactor(0.5, 0.5, 0.5, -0.01), 0.0);
    EXPECT_EQ(proto::horizonFactor(0.5, -0.01, 0.5, 0.5), 0.0);
    EXPECT_EQ(proto::horizonFactor(0.5f, 0.5f, 0.5f, 0.5f), 1.0f);
}

TEST_F(HorizonScene, ALightInFrontLightsThePlane) {
    EXPECT_GT(brightestLitFrom({0.0, 0.0, 0.0}), 0.5);
}

TEST_F(HorizonScene, ALightBehindThePlaneGivesNoLight) {
    EXPECT_EQ(brightestLitFrom({0.0, 0.1, 2.0}), 0.0);
    // Just below the horizon of every point, still nothing.
    EXPECT_EQ(brightestLitFrom({0.0, 0.0, 1.0001}), 0.0);
}

TEST_F(HorizonScene, AViewerBehindThePlaneSeesNoLight) {
    scene_.light.position = {0.0, 0.0, 0.0};
    scene_.viewer = {0.0, 0.0, 3.0};
    EXPECT_EQ(brightest(), 0.0);
}

TEST_F(HorizonScene, ShadingNormalsLeaningOverTheHorizonLeakNoLight) {
    // Vertex normals tilted 80° toward +x: they see a light far out along +x, behind the
    // plane's geometric horizon (z > 1), which the geometric normal does not.
    const Vec3f tilted{static_cast<float>(std::sin(80 * kPi / 180)), 0.0f,
                       static_cast<float>(-std::cos(80 * kPi / 180))};
    std::fill(mesh_.normals.begin(), mesh_.normals.end(), tilted);
    scene_.mesh = mesh_.view();
    EXPECT_EQ(brightestLitFrom({5.0, 0.0, 1.3}), 0.0);
    // The same light in front of the plane lights it.
    EXPECT_GT(brightestLitFrom({5.0, 0.0, 0.7}), 0.1);
}

TEST_F(HorizonScene, TheDirectViewHasTheSameHorizon) {
    scene_.light.position = {0.0, 0.1, 2.0};
    const DirectView direct = renderDirectView(scene_, scene_.projector.camera);
    EXPECT_EQ(*std::max_element(direct.radiance.values.begin(), direct.radiance.values.end()),
              0.0f);
}

}  // namespace
}  // namespace vpe::renderer
