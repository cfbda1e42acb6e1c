// SPDX-License-Identifier: MIT
// Material sampling: the UV convention, bilinear blending of maps and regions, and the
// evaluator against proto's definition.
#include "vpe/renderer/cpu/material_textures.h"

#include <cmath>

#include <gtest/gtest.h>

#include "vpe/proto/fourier_brdf.h"

#include "test_scenes.h"

namespace vpe::renderer {
namespace {

using testing::addRegion;
using testing::makeMaterial;

// 2 × 2 texels, M = 0: kd of texel (x, y) is 10·y + x + 1 in every channel, a0 = channel.
testing::OwnedMaterial tinyMaterial() {
    return makeMaterial(0, 2, 2, [](int x, int y, int k, int c) {
        return k == proto::kLambertIndex ? 10.0 * y + x + 1 : static_cast<double>(c);
    });
}

TEST(MaterialTextures, VZeroIsTheBottomRowAndTexelCentresAreExact) {
    const auto owned = tinyMaterial();
    const MaterialTextures material = owned.view();
    ASSERT_EQ(checkMaterialTextures(material), "");
    double coefficients[kMaxCoefficientsPerTexel];
    // Texel (0, 0), the top-left texel, has its centre at uv (0.25, 0.75).
    sampleMaterial(material, {0.25, 0.75}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[3 * proto::kLambertIndex + 0], 1.0);
    // Texel (1, 1), bottom right, at (0.75, 0.25).
    sampleMaterial(material, {0.75, 0.25}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[3 * proto::kLambertIndex + 1], 12.0);
    // Layout 3·k + c: a0 of channel 2.
    EXPECT_DOUBLE_EQ(coefficients[3 * proto::kConstantIndex + 2], 2.0);
    // Halfway between all four centres: their mean.
    sampleMaterial(material, {0.5, 0.5}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], (1 + 2 + 11 + 12) / 4.0);
    // Clamp to edge: the corners and beyond read the corner texels.
    sampleMaterial(material, {0.0, 1.0}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], 1.0);
    sampleMaterial(material, {1.3, -0.2}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], 12.0);
}

// A texture that tiles in u: left of texel 0's centre and right of the last one's, sampling
// blends the two edge columns (GL's REPEAT); v still clamps.
TEST(MaterialTextures, WrapsInUWhenTheMapsTile) {
    const auto owned = makeMaterial(0, 4, 2, [](int x, int y, int k, int) {
        return k == proto::kLambertIndex ? 10.0 * y + x + 1 : 0.0;
    });
    MaterialTextures material = owned.view();
    material.wrapU = true;
    double coefficients[kMaxCoefficientsPerTexel];
    // The seam, u = 0 or 1, halfway between texel 3's centre and texel 0's (top row: 4 and 1).
    for (const double u : {0.0, 1.0, -1.0, 2.0}) {
        sampleMaterial(material, {u, 0.75}, coefficients);
        EXPECT_DOUBLE_EQ(coefficients[0], (4 + 1) / 2.0) << u;
    }
    // A quarter texel left of texel 0's centre (u = 1/16): ¼ of texel 3, ¾ of texel 0.
    sampleMaterial(material, {1.0 / 16, 0.75}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], 0.25 * 4 + 0.75 * 1);
    // Texel centres are unchanged, and v clamps: beyond the bottom row reads it.
    sampleMaterial(material, {0.375, -0.5}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], 12.0);
    material.wrapU = false;
    sampleMaterial(material, {0.0, 0.75}, coefficients);
    EXPECT_DOUBLE_EQ(coefficients[0], 1.0);
}

TEST(MaterialTextures, RegionsBlendByTheirBilinearWeights) {
    auto owned = makeMaterial(0, 2, 2, [](int, int, int k, int) { return k == 0 ? 1.0 : 0.0; });
    owned.weights[0] = {1, 0, 1, 0};  // region 0 on the left column
    addRegion(
        owned, [](int, int, int k, int) { return k == 0 ? 3.0 : 0.0; },
        [](int x, int) { return x == 1 ? 1.0 : 0.0; });
    const MaterialTextures material = owned.view();
    ASSERT_EQ(checkMaterialTextures(material), "");
    double coefficients[kMaxCoefficientsPerTexel];
    for (const double u : {0.25, 0.4, 0.5, 0.6, 0.75}) {
        sampleMaterial(material, {u, 0.5}, coefficients);
        const double right = std::clamp(2 * u - 0.5, 0.0, 1.0);
        EXPECT_NEAR(coefficients[0], 1.0 * (1 - right) + 3.0 * right, 1e-7) << u;
    }
}

TEST(MaterialTextures, EvaluatesProtosModelPerChannel) {
    const int harmonics = 3;
    const auto owned = makeMaterial(harmonics, 1, 1, [](int, int, int k, int c) {
        return 0.1 * (k + 1) * (c + 1) * (k % 2 == 0 ? 1 : -1);
    });
    double coefficients[kMaxCoefficientsPerTexel];
    sampleMaterial(owned.view(), {0.3, 0.6}, coefficients);
    const Vec3d n{0, 0, 1};
    const Vec3d l = proto::normalized(Vec3d{0.3, 0.1, 1.0});
    const Vec3d v = proto::normalized(Vec3d{-0.5, 0.2, 1.0});
    const auto f = evaluateMaterial(coefficients, harmonics, n, l, v);
    const auto angles = proto::reflectionAngles(n, l, v);
    for (int c = 0; c < 3; ++c) {
        double channel[8];
        for (int k = 0; k < 8; ++k) {
            channel[k] = 0.1 * (k + 1) * (c + 1) * (k % 2 == 0 ? 1 : -1);
        }
        const double expected = proto::evaluateFourierBrdfDirect(
            channel, harmonics, std::acos(angles.cosThetaD), std::acos(angles.cosThetaS));
        EXPECT_NEAR(f[static_cast<std::size_t>(c)], expected, 1e-6);
    }
}

TEST(MaterialTextures, ReliefBlendsLikeTheCoefficientsAndTiltsThroughTheTangentFrame) {
    // Region 0 (left column) has a relief tilting toward +u; region 1 (right column) none.
    auto owned = makeMaterial(0, 2, 2, [](int, int, int, int) { return 0.0; });
    owned.weights[0] = {1, 0, 1, 0};
    addRegion(
        owned, [](int, int, int, int) { return 0.0; },
        [](int x, int) { return x == 1 ? 1.0 : 0.0; });
    MaterialTextures material = owned.view();
    EXPECT_FALSE(hasRelief(material));
    const std::vector<float> detail{0.6f, 0.0f, 0.6f, 0.0f, 0.6f, 0.0f, 0.6f, 0.0f};
    material.regions[0].detailNormals = detail;
    ASSERT_EQ(checkMaterialTextures(material), "");
    EXPECT_TRUE(hasRelief(material));
    // On the left column: region 0's (0.6, 0, 0.8); on the right: flat; halfway: their mean.
    Vec3d d = sampleDetailNormal(material, {0.25, 0.5});
    EXPECT_NEAR(d.x, 0.6, 1e-7);
    EXPECT_NEAR(d.z, 0.8, 1e-7);
    d = sampleDetailNormal(material, {0.5, 0.5});
    EXPECT_NEAR(d.x, 0.3, 1e-7);
    EXPECT_NEAR(d.z, 0.9, 1e-7);
    // A point on the plane z = 0 facing +z, u along −y and v along +x (a rotated mapping).
    SurfacePoint point;
    point.normal = {0, 0, 1};
    point.geometricNormal = {0, 0, 1};
    point.tangentU = {0, -2, 0};
    point.tangentV = {3, 0, 0};
    point.uv = {0.25, 0.5};
    const Vec3d n = shadingNormal(material, point);
    EXPECT_NEAR(n.x, 0.0, 1e-7);
    EXPECT_NEAR(n.y, -0.6, 1e-7);  // tilted toward +u
    EXPECT_NEAR(n.z, 0.8, 1e-7);
    point.uv = {0.75, 0.5};
    const Vec3d flat = shadingNormal(material, point);
    EXPECT_NEAR(flat.z, 1.0, 1e-12);
    material.regions[0].detailNormals = std::span<const float>(detail).first(6);
    EXPECT_NE(checkMaterialTextures(material), "");
}

TEST(MaterialTextures, ChecksSizes) {
    auto owned = tinyMaterial();
    MaterialTextures material = owned.view();
    material.harmonics = 1;
    EXPECT_NE(checkMaterialTextures(material), "");
    owned.weights[0] = {1, 1, 1};
    EXPECT_NE(checkMaterialTextures(owned.view()), "");
    material.regions.clear();
    EXPECT_NE(checkMaterialTextures(material), "");
}

}  // namespace
}  // namespace vpe::renderer
