// SPDX-License-Identifier: MIT
// The built-in vase: watertight but for its opening, outward unit normals, the UV layout and
// its seam, proportions, and the loader's checks.
#include "vpe/scene/procedural_vase.h"

#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/scene/screen_mesh.h"

#include "offline/scene/scene_test_support.h"
#include "support/test_data.h"

namespace vpe::scene {
namespace {

using namespace test;  // NOLINT: the shared helpers of scene_test_support.h
using testing::TemporaryFolder;

using PositionKey = std::tuple<float, float, float>;

PositionKey key(const Vec3f& p) {
    return {p.x, p.y, p.z};
}

TEST(ProceduralVase, IsWatertightExceptTheTopOpening) {
    const VaseParameters parameters;
    const ScreenMesh vase = makeProceduralVase(parameters);
    // Weld by exact position: the seam and the foot's hard edge repeat positions exactly.
    std::map<PositionKey, std::uint32_t> ids;
    std::vector<std::uint32_t> welded(vase.vertexCount());
    for (std::size_t i = 0; i < vase.vertexCount(); ++i) {
        welded[i] = ids.emplace(key(vase.positions[i]), static_cast<std::uint32_t>(ids.size()))
                        .first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < vase.triangleCount(); ++t) {
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t a = welded[vase.indices[3 * t + k]];
            const std::uint32_t b = welded[vase.indices[3 * t + (k + 1) % 3]];
            ASSERT_NE(a, b) << "degenerate edge in triangle " << t;
            ++directed[{a, b}];
        }
    }
    std::vector<Vec3f> weldedPosition(ids.size());
    for (std::size_t i = 0; i < vase.vertexCount(); ++i) {
        weldedPosition[welded[i]] = vase.positions[i];
    }
    int boundary = 0;
    for (const auto& [edge, count] : directed) {
        // Each directed edge once (consistent winding), its reverse once unless on the rim.
        ASSERT_EQ(count, 1);
        if (directed.count({edge.second, edge.first}) == 0) {
            ++boundary;
            EXPECT_FLOAT_EQ(weldedPosition[edge.first].y, static_cast<float>(parameters.height));
            EXPECT_FLOAT_EQ(weldedPosition[edge.second].y, static_cast<float>(parameters.height));
        }
    }
    EXPECT_EQ(boundary, parameters.segments);
}

TEST(ProceduralVase, NormalsAreUnitAndOutward) {
    const ScreenMesh vase = makeProceduralVase();
    for (std::size_t i = 0; i < vase.vertexCount(); ++i) {
        const Vec3f n = vase.normals[i], p = vase.positions[i];
        EXPECT_NEAR(std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z), 1.0f, 1e-6f);
        const float radial = n.x * p.x + n.z * p.z;
        if (p.y > 0) {
            EXPECT_GT(radial, 0.0f) << "vertex " << i;  // away from the axis
        } else {
            EXPECT_TRUE(n.y == -1.0f || radial > 0) << "vertex " << i;
        }
    }
    for (std::size_t t = 0; t < vase.triangleCount(); ++t) {
        const Vec3f f = faceNormal(vase, t);
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3f n = vase.normals[vase.indices[3 * t + k]];
            EXPECT_GT(f.x * n.x + f.y * n.y + f.z * n.z, 0.0f) << "triangle " << t;
        }
    }
}

TEST(ProceduralVase, UvsCoverTheUnitSquareWithTheSeamAtTheBack) {
    const ScreenMesh vase = makeProceduralVase();
    float uMin = 1, uMax = 0, vMin = 1, vMax = 0;
    for (std::size_t i = 0; i < vase.vertexCount(); ++i) {
        const Vec2f uv = vase.uvs[i];
        uMin = std::min(uMin, uv.x);
        uMax = std::max(uMax, uv.x);
        vMin = std::min(vMin, uv.y);
        vMax = std::max(vMax, uv.y);
        const Vec3f p = vase.positions[i];
        if (uv.x == 0.5f && p.y > 0) {
            EXPECT_GT(p.z, 0.0f);  // the front faces +z
            EXPECT_NEAR(p.x, 0.0f, 1e-7f);
        }
        if ((uv.x == 0.0f || uv.x == 1.0f) && p.y > 0) {
            EXPECT_LT(p.z, 0.0f);  // the seam is at the back
        }
        if (uv.x == 0.25f && p.y > 0) {
            EXPECT_LT(p.x, 0.0f);  // u grows left to right seen from the front
        }
    }
    EXPECT_EQ(uMin, 0.0f);
    EXPECT_EQ(uMax, 1.0f);
    EXPECT_EQ(vMin, 0.0f);
    EXPECT_EQ(vMax, 1.0f);
    // v rises with height along the side (vertices are stored ring by ring, foot to lip).
    for (std::size_t i = 0; i + 1 < vase.vertexCount(); ++i) {
        if (vase.positions[i].y > 0 && vase.positions[i + 1].y > vase.positions[i].y) {
            EXPECT_GT(vase.uvs[i + 1].y, vase.uvs[i].y);
        }
    }
}

TEST(ProceduralVase, HasAJarsProportions) {
    const VaseParameters parameters;
    EXPECT_NEAR(vaseRadius(0, parameters.height), 0.045, 1e-12);
    double widest = 0, widestAt = 0;
    for (int k = 0; k <= 1000; ++k) {
        const double y = parameters.height * k / 1000;
        if (vaseRadius(y, parameters.height) > widest) {
            widest = vaseRadius(y, parameters.height);
            widestAt = y;
        }
        // The slope is the radius's derivative.
        if (k > 0 && k < 1000) {
            const double h = 1e-6;
            const double numeric =
                (vaseRadius(y + h, parameters.height) - vaseRadius(y - h, parameters.height)) /
                (2 * h);
            EXPECT_NEAR(vaseRadiusSlope(y, parameters.height), numeric, 1e-4) << y;
        }
    }
    EXPECT_NEAR(widest, 0.08, 0.002);
    EXPECT_GT(widestAt, 0.04);
    EXPECT_LT(widestAt, 0.09);
    // Narrower neck than lip.
    EXPECT_LT(vaseRadius(0.93 * parameters.height, parameters.height),
              vaseRadius(parameters.height, parameters.height));
    const ScreenMesh vase = makeProceduralVase(parameters);
    float top = 0;
    for (const Vec3f& p : vase.positions) {
        top = std::max(top, p.y);
    }
    EXPECT_FLOAT_EQ(top, 0.15f);
}

TEST(ProceduralVase, PassesTheLoadersChecksUnchanged) {
    ScreenMesh vase = makeProceduralVase();
    const std::size_t triangles = vase.triangleCount(), vertices = vase.vertexCount();
    validateScreenMesh(vase, "vase");
    EXPECT_EQ(vase.triangleCount(), triangles);
    EXPECT_EQ(vase.vertexCount(), vertices);
    EXPECT_EQ(vertices, 128u + 129u * (8u + 97u));
}

TEST(ProceduralVase, RefusesBadParameters) {
    EXPECT_INPUT_ERROR(makeProceduralVase({0.15, 2, 10, 1}), "vase: segments must be 3..65536");
    EXPECT_INPUT_ERROR(makeProceduralVase({0.15, 16, 0, 1}), "vase: segments must be 3..65536");
    EXPECT_INPUT_ERROR(makeProceduralVase({-1, 16, 8, 1}),
                       "vase: height must be a positive number");
}

}  // namespace
}  // namespace vpe::scene
