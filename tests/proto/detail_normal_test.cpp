// SPDX-License-Identifier: MIT
// The relief's contract (proto/detail_normal.h): the tangent frame, applying a detail normal,
// and measuring one — inverse operations in the same frame.
#include "vpe/proto/detail_normal.h"

#include <cmath>

#include <gtest/gtest.h>

namespace vpe::proto {
namespace {

void expectNear(const Vec3d& a, const Vec3d& b, double tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(TangentFrame, IsOrthonormalWithTAlongUAndBAlongV) {
    const Vec3d n = normalized(Vec3d{0.2, 0.3, 0.9});
    // ∂X/∂u and ∂X/∂v of some mapping: neither unit nor orthogonal to n or each other.
    const Vec3d du{3.0, 0.4, -0.2}, dv{0.5, 2.0, 0.1};
    const TangentFrame<double> frame = tangentFrame(n, du, dv);
    EXPECT_NEAR(dot(frame.t, frame.t), 1.0, 1e-12);
    EXPECT_NEAR(dot(frame.b, frame.b), 1.0, 1e-12);
    EXPECT_NEAR(dot(frame.t, frame.n), 0.0, 1e-12);
    EXPECT_NEAR(dot(frame.b, frame.n), 0.0, 1e-12);
    EXPECT_NEAR(dot(frame.t, frame.b), 0.0, 1e-12);
    EXPECT_GT(dot(frame.t, du), 0.0);
    EXPECT_GT(dot(frame.b, dv), 0.0);
    expectNear(cross(frame.n, frame.t), frame.b, 1e-12);
}

TEST(TangentFrame, AMirroredMappingMirrorsB) {
    const Vec3d n{0, 0, 1};
    const TangentFrame<double> frame = tangentFrame(n, Vec3d{1, 0, 0}, Vec3d{0, -1, 0});
    expectNear(frame.t, {1, 0, 0}, 1e-15);
    expectNear(frame.b, {0, -1, 0}, 1e-15);  // along +v, not n × t
}

TEST(TangentFrame, DegenerateMappingsStillGiveAFrame) {
    const Vec3d n{0, 0, 1};
    // u along the normal: t from v.
    TangentFrame<double> frame = tangentFrame(n, Vec3d{0, 0, 2}, Vec3d{0, 1, 0});
    expectNear(frame.b, {0, 1, 0}, 1e-15);
    EXPECT_NEAR(dot(frame.t, frame.b), 0.0, 1e-15);
    // No mapping at all (a triangle with equal uvs): any frame about n.
    frame = tangentFrame(n, Vec3d{0, 0, 0}, Vec3d{0, 0, 0});
    EXPECT_NEAR(dot(frame.t, frame.t), 1.0, 1e-12);
    EXPECT_NEAR(dot(frame.t, n), 0.0, 1e-12);
    EXPECT_NEAR(dot(frame.b, n), 0.0, 1e-12);
}

TEST(DetailNormal, FlatLeavesTheNormalAndMeasuringInvertsApplying) {
    const Vec3d n = normalized(Vec3d{-0.4, 0.5, 0.7});
    const TangentFrame<double> frame = tangentFrame(n, Vec3d{0.7, 0.1, 0.3}, Vec3d{0, 1, -0.6});
    expectNear(applyDetailNormal(frame, Vec3d{0, 0, 1}), n, 1e-15);
    for (const Vec3d d : {Vec3d{0.3, -0.2, 0}, Vec3d{-0.6, 0.1, 0}, Vec3d{0.05, 0.7, 0}}) {
        const Vec3d detail = detailNormalFromXy(d.x, d.y);
        EXPECT_NEAR(dot(detail, detail), 1.0, 1e-15);
        const Vec3d tilted = applyDetailNormal(frame, detail);
        // The tilt: as far from n as the detail normal is from (0, 0, 1), toward t·x + b·y.
        EXPECT_NEAR(dot(tilted, n), detail.z, 1e-12);
        EXPECT_NEAR(dot(tilted, frame.t), detail.x, 1e-12);
        EXPECT_NEAR(dot(tilted, frame.b), detail.y, 1e-12);
        expectNear(detailNormalIn(frame, tilted), detail, 1e-12);
    }
}

TEST(DetailNormal, MeasuringKeepsANormalAboveTheMacroSurface) {
    const TangentFrame<double> frame{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Vec3d below = detailNormalIn(frame, normalized(Vec3d{1, 1, -0.5}));
    EXPECT_NEAR(below.z, kMinDetailZ, 1e-15);
    EXPECT_NEAR(dot(below, below), 1.0, 1e-12);
    EXPECT_NEAR(below.x, below.y, 1e-15);  // same direction, tilted as far as allowed
    EXPECT_GT(below.x, 0.0);
}

TEST(DetailNormal, StoredXyOutsideTheDiscIsScaledOntoIt) {
    const Vec3d d = detailNormalFromXy(0.9, 0.9);
    EXPECT_NEAR(d.x, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(d.y, std::sqrt(0.5), 1e-15);
    EXPECT_EQ(d.z, 0.0);
}

}  // namespace
}  // namespace vpe::proto
