// SPDX-License-Identifier: MIT
// θd and θs from normal, light and view.
#include "vpe/proto/reflection_geometry.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

using V = Vec3<double>;

double degrees(double cosine) {
    return std::acos(cosine) * 180.0 / M_PI;
}

TEST(ReflectionAngles, HeadOnLightMirrorsIntoTheViewer) {
    const auto angles = reflectionAngles(V{0, 0, 1}, V{0, 0, 1}, V{0, 0, 1});
    EXPECT_DOUBLE_EQ(angles.cosThetaD, 1.0);
    EXPECT_DOUBLE_EQ(angles.cosThetaS, 1.0);
}

TEST(ReflectionAngles, FlatSurfaceLightAtElevation) {
    // Light 30° above the horizon: θd = 60°; its mirror is 60° from the normal on the other
    // side, so 60° from a viewer straight above.
    const double e = 30.0 * M_PI / 180.0;
    const auto angles = reflectionAngles(V{0, 0, 1}, V{std::cos(e), 0, std::sin(e)}, V{0, 0, 1});
    EXPECT_NEAR(degrees(angles.cosThetaD), 60.0, 1e-9);
    EXPECT_NEAR(degrees(angles.cosThetaS), 60.0, 1e-9);
}

TEST(ReflectionAngles, MirrorConfigurationGivesThetaSZero) {
    const double a = 40.0 * M_PI / 180.0;
    const V light{std::sin(a), 0, std::cos(a)};
    const V viewer{-std::sin(a), 0, std::cos(a)};
    const auto angles = reflectionAngles(V{0, 0, 1}, light, viewer);
    EXPECT_NEAR(angles.cosThetaS, 1.0, 1e-12);
    EXPECT_NEAR(degrees(angles.cosThetaD), 40.0, 1e-9);
}

TEST(ReflectionAngles, LightBelowTheHorizonHasNegativeCosThetaD) {
    const auto angles = reflectionAngles(V{0, 0, 1}, normalized(V{1, 0, -0.2}), V{0, 0, 1});
    EXPECT_LT(angles.cosThetaD, 0.0);
}

TEST(ReflectionAngles, EqualsExplicitMirrorVectorForRandomGeometry) {
    std::mt19937 random(3);
    std::normal_distribution<double> gaussian;
    for (int i = 0; i < 1000; ++i) {
        const V n = normalized(V{gaussian(random), gaussian(random), gaussian(random)});
        const V l = normalized(V{gaussian(random), gaussian(random), gaussian(random)});
        const V v = normalized(V{gaussian(random), gaussian(random), gaussian(random)});
        const double nl = dot(n, l);
        const V r{2 * nl * n.x - l.x, 2 * nl * n.y - l.y, 2 * nl * n.z - l.z};
        const auto angles = reflectionAngles(n, l, v);
        EXPECT_NEAR(angles.cosThetaD, nl, 1e-12);
        EXPECT_NEAR(angles.cosThetaS, std::clamp(dot(r, v), -1.0, 1.0), 1e-12);
        EXPECT_GE(angles.cosThetaS, -1.0);
        EXPECT_LE(angles.cosThetaS, 1.0);
    }
}

}  // namespace
}  // namespace vpe::proto
