// SPDX-License-Identifier: MIT
// RayCaster: agrees with testing every triangle, has no cracks, interpolates hits.
#include "vpe/renderer/cpu/ray_caster.h"

#include <cmath>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "vpe/renderer/cpu/surface_point.h"

#include "test_scenes.h"

namespace vpe::renderer {
namespace {

Vec3d sub(const Vec3d& a, const Vec3d& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Vec3d toD(const Vec3f& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// Every triangle, no slack: the nearest t.
std::optional<double> bruteForce(const RenderMesh& mesh, const Vec3d& o, const Vec3d& d) {
    std::optional<double> best;
    for (std::size_t i = 0; i < mesh.triangleCount(); ++i) {
        const Vec3d v0 = toD(mesh.positions[mesh.indices[3 * i]]);
        const Vec3d e1 = sub(toD(mesh.positions[mesh.indices[3 * i + 1]]), v0);
        const Vec3d e2 = sub(toD(mesh.positions[mesh.indices[3 * i + 2]]), v0);
        const Vec3d p = proto::cross(d, e2);
        const double det = proto::dot(e1, p);
        if (det == 0) {
            continue;
        }
        const Vec3d s = sub(o, v0);
        const double b1 = proto::dot(s, p) / det;
        const Vec3d q = proto::cross(s, e1);
        const double b2 = proto::dot(d, q) / det;
        const double t = proto::dot(e2, q) / det;
        if (b1 >= 0 && b2 >= 0 && b1 + b2 <= 1 && t > 0 && (!best || t < *best)) {
            best = t;
        }
    }
    return best;
}

TEST(RayCaster, AgreesWithTestingEveryTriangle) {
    const auto owned = testing::makeVaseMesh(48, 24);
    const RenderMesh mesh = owned.view();
    const RayCaster caster(mesh);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3d origin{0.4 * unit(random), 0.075 + 0.4 * unit(random), 0.4 * unit(random)};
        const Vec3d target{0.07 * unit(random), 0.075 + 0.08 * unit(random), 0.07 * unit(random)};
        const Vec3d d = sub(target, origin);
        const auto expected = bruteForce(mesh, origin, d);
        const auto hit = caster.closestHit(origin, d);
        ASSERT_EQ(hit.has_value(), expected.has_value()) << i;
        if (hit) {
            ++hits;
            EXPECT_NEAR(hit->t, *expected, 1e-9) << i;
            EXPECT_EQ(caster.anyHit(origin, d, 0.0, hit->t * 1.000001), true);
            EXPECT_EQ(caster.anyHit(origin, d, 0.0, hit->t * 0.999999), false);
        }
    }
    EXPECT_GT(hits, 1000);
}

TEST(RayCaster, RaysThroughVerticesAndEdgesDoNotSlipThrough) {
    const auto owned = testing::makeVaseMesh(32, 16);
    const RenderMesh mesh = owned.view();
    const RayCaster caster(mesh);
    // From the axis outwards through every interior vertex and edge midpoint: the surface is
    // closed around the axis, so every such ray hits it.
    int misses = 0;
    for (std::size_t i = 0; i < mesh.triangleCount(); ++i) {
        for (int e = 0; e < 3; ++e) {
            const Vec3d a = toD(mesh.positions[mesh.indices[3 * i + static_cast<std::size_t>(e)]]);
            const Vec3d b =
                toD(mesh.positions[mesh.indices[3 * i + static_cast<std::size_t>((e + 1) % 3)]]);
            for (const Vec3d& p :
                 {a, Vec3d{0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z)}}) {
                if (p.y <= 0 || p.y >= 0.15) {
                    continue;  // the open ends
                }
                const Vec3d origin{0, p.y, 0};
                if (!caster.closestHit(origin, sub(p, origin))) {
                    ++misses;
                }
            }
        }
    }
    EXPECT_EQ(misses, 0);
}

TEST(RayCaster, SurfacePointInterpolatesAndFacesTheRay) {
    const auto owned = testing::makePlaneMesh(1.0, 0.5, 4);
    const RenderMesh mesh = owned.view();
    const RayCaster caster(mesh);
    const Vec3d d{0.1, -0.2, 1.0};
    const auto hit = caster.closestHit({0, 0, 0}, d);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->t, 1.0, 1e-12);
    const SurfacePoint front = surfacePoint(mesh, {0, 0, 0}, d, *hit);
    EXPECT_NEAR(front.position.x, 0.1, 1e-12);
    EXPECT_NEAR(front.uv.x, 0.6, 1e-7);
    EXPECT_NEAR(front.uv.y, 0.3, 1e-7);
    EXPECT_NEAR(front.normal.z, -1.0, 1e-12);
    // From behind, the surface turns its normal to the ray.
    const Vec3d origin{0, 0, 2};
    const Vec3d back{0.1, -0.2, -1.0};
    const auto hitBack = caster.closestHit(origin, back);
    ASSERT_TRUE(hitBack.has_value());
    const SurfacePoint behind = surfacePoint(mesh, origin, back, *hitBack);
    EXPECT_NEAR(behind.normal.z, 1.0, 1e-12);
    EXPECT_NEAR(behind.geometricNormal.z, 1.0, 1e-12);
    EXPECT_FALSE(caster.closestHit({0, 0, 0}, {0, 0, -1}).has_value());
    EXPECT_FALSE(caster.closestHit({0, 0, 0}, d, 0.0, 0.99).has_value());
}

}  // namespace
}  // namespace vpe::renderer
