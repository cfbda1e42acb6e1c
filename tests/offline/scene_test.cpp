// SPDX-License-Identifier: MIT
// The inputs of `vpe bake`: screen meshes (OBJ, PLY), the procedural vase, projector
// calibration files, projector response curves and scene settings — round trips, and every
// refusal with its one-line message. Fixture files are written by the tests.
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/response_input.h"
#include "vpe/scene/scene_settings.h"
#include "vpe/scene/screen_mesh.h"

#include "support/test_data.h"

namespace vpe::scene {
namespace {

using testing::TemporaryFolder;

// The message of the InputError `f` throws; fails the test when it throws none.
std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "no InputError thrown";
    return {};
}

#define EXPECT_INPUT_ERROR(statement, fragment)                                            \
    do {                                                                                   \
        const std::string message_ = errorOf([&] { (void)(statement); });                  \
        EXPECT_NE(message_.find(fragment), std::string::npos) << message_;                 \
        EXPECT_EQ(message_.find('\n'), std::string::npos) << "not one line: " << message_; \
    } while (false)

void writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream stream(path, std::ios::binary);
    stream << text;
}

double distance(const Vec3f& a, const Vec3f& b) {
    const double dx = static_cast<double>(a.x) - static_cast<double>(b.x);
    const double dy = static_cast<double>(a.y) - static_cast<double>(b.y);
    const double dz = static_cast<double>(a.z) - static_cast<double>(b.z);
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

Vec3f faceNormal(const ScreenMesh& mesh, std::size_t t) {
    const Vec3f a = mesh.positions[mesh.indices[3 * t]];
    const Vec3f b = mesh.positions[mesh.indices[3 * t + 1]];
    const Vec3f c = mesh.positions[mesh.indices[3 * t + 2]];
    const Vec3f e1{b.x - a.x, b.y - a.y, b.z - a.z}, e2{c.x - a.x, c.y - a.y, c.z - a.z};
    return {e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
}

// Every corner of every triangle of `actual` matches `expected` (same triangle order, as the
// loader keeps the file's face order).
void expectSameTriangles(const ScreenMesh& expected, const ScreenMesh& actual) {
    ASSERT_EQ(expected.triangleCount(), actual.triangleCount());
    for (std::size_t i = 0; i < expected.indices.size(); ++i) {
        const std::uint32_t e = expected.indices[i], a = actual.indices[i];
        ASSERT_LT(distance(expected.positions[e], actual.positions[a]), 1e-6) << "corner " << i;
        ASSERT_LT(distance(expected.normals[e], actual.normals[a]), 1e-5) << "corner " << i;
        ASSERT_NEAR(expected.uvs[e].x, actual.uvs[a].x, 1e-6) << "corner " << i;
        ASSERT_NEAR(expected.uvs[e].y, actual.uvs[a].y, 1e-6) << "corner " << i;
    }
}

// A unit square in the z = 0 plane facing +z, as two triangles, in OBJ.
constexpr const char* kSquareObj =
    "# a square\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3 4/4\n";  // a quad: triangulated on load

// ----------------------------------------------------------------------------------------
// Screen meshes

TEST(ScreenMesh, ObjRoundTripKeepsEveryCorner) {
    TemporaryFolder folder;
    VaseParameters small;
    small.segments = 12;
    small.rings = 6;
    small.baseRings = 2;
    const ScreenMesh vase = makeProceduralVase(small);
    writeScreenMeshObj(vase, folder / "vase.obj");
    const ScreenMesh loaded = loadScreenMesh(folder / "vase.obj");
    EXPECT_EQ(loaded.vertexCount(), vase.vertexCount());
    expectSameTriangles(vase, loaded);
    // Nothing but the file is left behind (the write was atomic).
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 1);
}

TEST(ScreenMesh, ObjQuadsAreTriangulatedAndNormalsGenerated) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj", kSquareObj);
    const ScreenMesh mesh = loadScreenMesh(folder / "square.obj");
    EXPECT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.vertexCount(), 4u);
    for (const Vec3f& n : mesh.normals) {
        EXPECT_NEAR(n.z, 1.0f, 1e-6f);
    }
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        EXPECT_GT(faceNormal(mesh, t).z, 0.0f);  // winding kept: counter-clockwise from +z
    }
}

TEST(ScreenMesh, UnitScaleConvertsToMetres) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj", kSquareObj);
    const ScreenMesh mesh = loadScreenMesh(folder / "square.obj", {0.001});
    float largest = 0;
    for (const Vec3f& p : mesh.positions) {
        largest = std::max({largest, p.x, p.y});
    }
    EXPECT_FLOAT_EQ(largest, 0.001f);
}

std::string plyHeader(const char* format, int vertices, int faces, bool withNormals) {
    std::string header =
        std::string("ply\nformat ") + format + " 1.0\ncomment made by scene_test\nelement vertex " +
        std::to_string(vertices) + "\nproperty float x\nproperty float y\nproperty float z\n";
    if (withNormals) {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    header += "property float s\nproperty float t\nelement face " + std::to_string(faces) +
              "\nproperty list uchar int vertex_indices\nend_header\n";
    return header;
}

// The vase as a binary little-endian PLY, optionally with one number replaced: component
// 0..7 (x y z nx ny nz s t) of one vertex.
void writeBinaryPly(const ScreenMesh& mesh, const std::filesystem::path& path,
                    std::size_t poisonedVertex = SIZE_MAX, float poison = 0,
                    std::size_t poisonedComponent = 1) {
    std::ofstream stream(path, std::ios::binary);
    stream << plyHeader("binary_little_endian", static_cast<int>(mesh.vertexCount()),
                        static_cast<int>(mesh.triangleCount()), true);
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        float values[8] = {mesh.positions[i].x, mesh.positions[i].y, mesh.positions[i].z,
                           mesh.normals[i].x,   mesh.normals[i].y,   mesh.normals[i].z,
                           mesh.uvs[i].x,       mesh.uvs[i].y};
        if (i == poisonedVertex) {
            values[poisonedComponent] = poison;
        }
        stream.write(reinterpret_cast<const char*>(values), sizeof values);
    }
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const unsigned char three = 3;
        stream.write(reinterpret_cast<const char*>(&three), 1);
        for (std::size_t k = 0; k < 3; ++k) {
            const auto index = static_cast<std::int32_t>(mesh.indices[3 * t + k]);
            stream.write(reinterpret_cast<const char*>(&index), sizeof index);
        }
    }
}

TEST(ScreenMesh, BinaryPlyRoundTripKeepsEveryCorner) {
    TemporaryFolder folder;
    VaseParameters small;
    small.segments = 10;
    small.rings = 5;
    small.baseRings = 2;
    const ScreenMesh vase = makeProceduralVase(small);
    writeBinaryPly(vase, folder / "vase.ply");
    const ScreenMesh loaded = loadScreenMesh(folder / "vase.ply");
    EXPECT_EQ(loaded.vertexCount(), vase.vertexCount());
    expectSameTriangles(vase, loaded);
}

TEST(ScreenMesh, AsciiPlyWithoutNormalsGetsSmoothNormals) {
    TemporaryFolder folder;
    writeFile(folder / "square.ply", plyHeader("ascii", 4, 2, false) +
                                         "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n"
                                         "3 0 1 2\n3 0 2 3\n");
    const ScreenMesh mesh = loadScreenMesh(folder / "square.ply");
    EXPECT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.vertexCount(), 4u);
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        EXPECT_NEAR(mesh.normals[i].z, 1.0f, 1e-6f);
        // s, t carried through as u, v.
        EXPECT_FLOAT_EQ(mesh.uvs[i].x, mesh.positions[i].x);
        EXPECT_FLOAT_EQ(mesh.uvs[i].y, mesh.positions[i].y);
    }
}

TEST(ScreenMesh, DegenerateTrianglesAreDroppedWithTheirVertices) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj", std::string(kSquareObj) +
                                         "v 2 0 0\nv 3 0 0\nv 4 0 0\nvt 0.5 0.5\n"
                                         "f 5/5 6/5 7/5\n");  // collinear
    const ScreenMesh mesh = loadScreenMesh(folder / "square.obj");
    EXPECT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.vertexCount(), 4u);
}

TEST(ScreenMesh, UvsSlightlyOutsideAreClamped) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt -0.0004 0\nvt 1.0004 0\nvt 1 1\nf 1/1 2/2 3/3\n");
    const ScreenMesh mesh = loadScreenMesh(folder / "square.obj");
    for (const Vec2f& uv : mesh.uvs) {
        EXPECT_GE(uv.x, 0.0f);
        EXPECT_LE(uv.x, 1.0f);
    }
}

TEST(ScreenMesh, RefusesMissingFile) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "absent.obj"),
                       "absent.obj: cannot open mesh: no such file");
}

TEST(ScreenMesh, RefusesOtherFormats) {
    TemporaryFolder folder;
    writeFile(folder / "square.stl", "solid x\nendsolid x\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "square.stl"),
                       "square.stl: unsupported mesh format '.stl' (vpe reads .obj and .ply)");
}

TEST(ScreenMesh, RefusesUnparsableFiles) {
    TemporaryFolder folder;
    writeFile(folder / "broken.ply", "ply\nformat ascii 1.0\nelement vertex banana\nend_header\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "broken.ply"), "broken.ply: cannot parse mesh");
    writeFile(folder / "empty.obj", "");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "empty.obj"), "empty.obj: cannot parse mesh");
}

TEST(ScreenMesh, RefusesFilesWithoutTriangles) {
    TemporaryFolder folder;
    writeFile(folder / "lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nl 1 2\nl 2 3\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "lines.obj"),
                       "lines.obj: no triangles: a screen mesh needs faces, not only points or "
                       "lines");
    writeFile(folder / "cloud.ply",
              plyHeader("ascii", 3, 0, false) + "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "cloud.ply"), "cloud.ply: no triangles");
    writeFile(folder / "text.obj", "this is not a mesh\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "text.obj"), "text.obj: no triangles");
}

TEST(ScreenMesh, RefusesMeshesWithoutUvs) {
    TemporaryFolder folder;
    writeFile(folder / "plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "plain.obj"),
                       "plain.obj: no texture coordinates: a screen mesh needs UVs");
}

TEST(ScreenMesh, RefusesNonFinitePositions) {
    TemporaryFolder folder;
    VaseParameters small;
    small.segments = 6;
    small.rings = 2;
    small.baseRings = 1;
    const ScreenMesh vase = makeProceduralVase(small);
    writeBinaryPly(vase, folder / "nan.ply", 7, std::nanf(""));
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "nan.ply"),
                       "nan.ply: a vertex has a position that is not a finite number");
    writeFile(folder / "nan.obj", "v 0 0 0\nv 1 nan 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "nan.obj"),
                       "nan.obj: a vertex has a position that is not a finite number (1, nan, 0)");
    writeBinaryPly(vase, folder / "inf.ply", 7, INFINITY);
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "inf.ply"),
                       "inf.ply: a vertex has a position that is not a finite number (");
    writeBinaryPly(vase, folder / "nanuv.ply", 3, std::nanf(""), 7);
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "nanuv.ply"),
                       "nanuv.ply: a vertex has texture coordinates that are not finite numbers");
}

TEST(ScreenMesh, RefusesUvsOutsideTheUnitSquare) {
    TemporaryFolder folder;
    writeFile(folder / "tiled.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 2 0\nvt 2 1\nf 1/1 2/2 3/3\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "tiled.obj"),
                       "has texture coordinates (2, 0) outside [0, 1]; vpe does not wrap");
}

TEST(ScreenMesh, RefusesMeshesOfOnlyDegenerateTriangles) {
    TemporaryFolder folder;
    writeFile(folder / "flat.obj",
              "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nvt 0 0\nf 1/1 2/1 3/1\nf 2/1 3/1 4/1\n");
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "flat.obj"),
                       "flat.obj: all 2 triangles are degenerate (zero area)");
}

TEST(ScreenMesh, RefusesMoreVerticesThan32BitIndicesReach) {
    EXPECT_NO_THROW(requireIndexableVertexCount(4294967295u, "big.ply"));
    EXPECT_INPUT_ERROR(requireIndexableVertexCount(4294967296u, "big.ply"),
                       "big.ply: 4294967296 vertices: more than 32-bit indices can address");
}

TEST(ScreenMesh, ValidationRefusesBadIndicesInMemory) {
    ScreenMesh mesh = makeProceduralVase({0.15, 4, 1, 1});
    mesh.indices.back() = 100000;
    EXPECT_INPUT_ERROR(validateScreenMesh(mesh, "memory"), "memory: triangle ");
}

TEST(ScreenMesh, LoadingPrintsNothing) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj", kSquareObj);
    writeFile(folder / "broken.ply", "ply\nformat ascii 1.0\nelement vertex x\nend_header\n");
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    loadScreenMesh(folder / "square.obj");
    errorOf([&] { loadScreenMesh(folder / "broken.ply"); });
    const std::string out = ::testing::internal::GetCapturedStdout();
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(out, "");
    EXPECT_EQ(err, "");
}

// ----------------------------------------------------------------------------------------
// The procedural vase

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

// ----------------------------------------------------------------------------------------
// Projector calibration

ProjectorCalibration sampleCalibration() {
    ProjectorCalibration c = makeDemoProjector(0.8);
    c.distortion = {0.01, -0.002, 0.0003, -0.0004, 0.0005};
    c.K[1] = 0.25;  // a little skew
    return c;
}

void expectSameCalibration(const ProjectorCalibration& a, const ProjectorCalibration& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    for (std::size_t i = 0; i < 9; ++i) {
        EXPECT_NEAR(a.K[i], b.K[i], 1e-12 * std::max(1.0, std::fabs(a.K[i]))) << i;
        EXPECT_NEAR(a.R[i], b.R[i], 1e-15) << i;
    }
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_NEAR(a.distortion[i], b.distortion[i], 1e-16) << i;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.T[i], b.T[i], 1e-15) << i;
    }
}

TEST(ProjectorCalibration, RoundTripsThroughYamlXmlAndJson) {
    TemporaryFolder folder;
    const ProjectorCalibration written = sampleCalibration();
    for (const char* name : {"projector.yml", "projector.xml", "projector.json"}) {
        SCOPED_TRACE(name);
        writeProjectorCalibration(written, folder / name);
        expectSameCalibration(written, readProjectorCalibration(folder / name));
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 3);
    EXPECT_INPUT_ERROR(writeProjectorCalibration(written, folder / "projector.txt"),
                       "unsupported calibration format '.txt'");
}

// What procam-calibration's Application::calibrate writes (numbers from a made-up rig): no
// resolution, T in millimetres.
constexpr const char* kProcamYaml = R"(%YAML:1.0
cam_K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 2.3e+03, 0., 1.2e+03, 0., 2.3e+03, 9.0e+02, 0., 0., 1. ]
cam_kc: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ 0.1, -0.2, 0., 0., 0. ]
proj_K: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 1.8e+03, 0., 5.1e+02, 0., 1.8e+03, 7.5e+02, 0., 0., 1. ]
proj_kc: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -0.05, 0.1, 0.001, 0.002, 0. ]
R: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 0.9950041652780258, 0., 0.09983341664682815, 0., 1., 0., -0.09983341664682815, 0., 0.9950041652780258 ]
T: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ -150., 10., 20. ]
b: 0.3
m: 5
stereo_error: 0.42
)";

TEST(ProjectorCalibration, ReadsProcamCalibrationFilesWithTheirUnitAndResolution) {
    TemporaryFolder folder;
    writeFile(folder / "calibration.yml", kProcamYaml);
    ProjectorCalibrationOverrides overrides;
    overrides.width = 1024;
    overrides.height = 768;
    overrides.metresPerUnit = 0.001;
    const ProjectorCalibration c = readProjectorCalibration(folder / "calibration.yml", overrides);
    EXPECT_EQ(c.width, 1024);
    EXPECT_EQ(c.height, 768);
    EXPECT_DOUBLE_EQ(c.K[0], 1800);
    EXPECT_DOUBLE_EQ(c.K[2], 510);
    EXPECT_DOUBLE_EQ(c.K[5], 750);
    EXPECT_DOUBLE_EQ(c.distortion[0], -0.05);
    EXPECT_DOUBLE_EQ(c.distortion[3], 0.002);
    EXPECT_DOUBLE_EQ(c.T[0], -0.15);
    EXPECT_DOUBLE_EQ(c.R[2], 0.09983341664682815);

    // Without a resolution the file is incomplete; without a unit, 150 "m" is implausible.
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "calibration.yml"),
                       "calibration.yml: no projector resolution (keys proj_width/proj_height "
                       "or image_width/image_height): give it on the command line");
    overrides.metresPerUnit.reset();
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "calibration.yml", overrides),
                       "calibration.yml: T: the projector would be");
}

// A vpe-style YAML calibration with one line replaced.
std::string yamlWith(const std::string& key, const std::string& value) {
    std::map<std::string, std::string> entries{
        {"proj_width", "1920"},
        {"proj_height", "1080"},
        {"proj_K",
         "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 2000., 0., "
         "959.5, 0., 2000., 539.5, 0., 0., 1. ]"},
        {"proj_kc",
         "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., "
         "0., 0. ]"},
        {"R",
         "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., "
         "-1., 0., 0., 0., -1. ]"},
        {"T", "!!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0., 0.075, 0.8 ]"},
        {"length_unit", "\"m\""},
    };
    if (value.empty()) {
        entries.erase(key);
    } else {
        entries[key] = value;
    }
    std::string text = "%YAML:1.0\n---\n";
    for (const auto& [k, v] : entries) {
        text += k + ": " + v + "\n";
    }
    return text;
}

std::string matrix(int rows, int cols, const std::string& data) {
    return "!!opencv-matrix\n   rows: " + std::to_string(rows) +
           "\n   cols: " + std::to_string(cols) + "\n   dt: d\n   data: [ " + data + " ]";
}

TEST(ProjectorCalibration, ReadsTheBaseFixture) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("", ""));
    const ProjectorCalibration c = readProjectorCalibration(folder / "p.yml");
    EXPECT_EQ(c.width, 1920);
    const Vec3d centre = c.center();
    EXPECT_NEAR(centre.z, 0.8, 1e-15);
    EXPECT_NEAR(centre.y, 0.075, 1e-15);
}

TEST(ProjectorCalibration, ReadsARodriguesRotationAndImageSizeKeys) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("R", matrix(3, 1, "3.141592653589793, 0., 0.")));
    const ProjectorCalibration c = readProjectorCalibration(folder / "p.yml");
    const std::array<double, 9> flipped{1, 0, 0, 0, -1, 0, 0, 0, -1};
    for (std::size_t i = 0; i < 9; ++i) {
        EXPECT_NEAR(c.R[i], flipped[i], 1e-12);
    }
    std::string other = yamlWith("proj_width", "");
    other = other.substr(0, other.find("proj_height")) +
            other.substr(other.find('\n', other.find("proj_height")) + 1);
    writeFile(folder / "q.yml", other + "image_width: 800\nimage_height: 600\n");
    const ProjectorCalibration q = readProjectorCalibration(folder / "q.yml");
    EXPECT_EQ(q.width, 800);
    EXPECT_EQ(q.height, 600);
}

TEST(ProjectorCalibration, RefusesEachBadKeyByName) {
    TemporaryFolder folder;
    const auto refuse = [&](const std::string& key, const std::string& value,
                            const std::string& fragment) {
        SCOPED_TRACE(key + " = " + value);
        writeFile(folder / "p.yml", yamlWith(key, value));
        EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.yml"), "p.yml: " + fragment);
    };
    refuse("proj_K", "", "proj_K: missing");
    refuse("R", "", "R: missing");
    refuse("T", "", "T: missing");
    refuse("proj_K", matrix(3, 3, "-2000., 0., 959.5, 0., 2000., 539.5, 0., 0., 1."),
           "proj_K: focal lengths must be positive (fx = -2000, fy = 2000)");
    refuse("proj_K", matrix(3, 3, "2000., 0., 959.5, 0., 0., 539.5, 0., 0., 1."),
           "proj_K: focal lengths must be positive");
    refuse("proj_K", matrix(3, 3, "2000., 0., 959.5, 0., 2000., 539.5, 0., 0., 2."),
           "proj_K: not an intrinsic matrix");
    refuse("proj_K", matrix(2, 3, "2000., 0., 959.5, 0., 2000., 539.5"),
           "proj_K: expected a 3x3 matrix, found 2x3");
    refuse("proj_K", matrix(3, 3, "2000., 0., .nan, 0., 2000., 539.5, 0., 0., 1."),
           "proj_K: element 2 is not a finite number");
    refuse("proj_K", "banana", "proj_K: not a matrix of numbers");
    refuse("proj_kc", matrix(1, 8, "0., 0., 0., 0., 0., 0.1, 0., 0."),
           "proj_kc: coefficient 6 is not zero");
    refuse("proj_kc", matrix(1, 3, "0., 0., 0."), "proj_kc: expected 4 or 5 distortion");
    refuse("R", matrix(3, 3, "1., 0., 0., 0., 1., 0.01, 0., 0., 1."),
           "R: not orthonormal (RᵀR differs from I by");
    refuse("R", matrix(3, 3, "1., 0., 0., 0., 1., 0., 0., 0., -1."),
           "R: determinant -1, not +1 (a reflection, not a rotation)");
    refuse("T", matrix(3, 1, "0., .inf, 0.8"), "T: element 1 is not a finite number");
    refuse("T", matrix(2, 1, "0., 0.8"), "T: expected a 3-vector, found 2x1");
    refuse("proj_width", "0", "projector resolution 0x1080 is outside 1..8192");
    refuse("proj_height", "9000", "projector resolution 1920x9000 is outside 1..8192");
    refuse("proj_width", "19.5", "proj_width: expected a whole number of pixels");
    refuse("proj_height", "", "proj_height: missing (given proj_width without it)");
    refuse("length_unit", "\"furlong\"", "length_unit: 'furlong' is not m, cm or mm");
}

TEST(ProjectorCalibration, RefusesConflictingResolution) {
    TemporaryFolder folder;
    writeFile(folder / "p.yml", yamlWith("", ""));
    ProjectorCalibrationOverrides overrides;
    overrides.width = 1280;
    overrides.height = 720;
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "p.yml", overrides),
                       "p.yml: proj_width: the file says 1920x1080 but 1280x720 was given");
    overrides.width = 1920;
    overrides.height = 1080;
    EXPECT_EQ(readProjectorCalibration(folder / "p.yml", overrides).width, 1920);
}

TEST(ProjectorCalibration, RefusesMissingAndUnparsableFiles) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "absent.yml"),
                       "absent.yml: cannot open projector calibration: no such file");
    writeFile(folder / "junk.yml", "%YAML:1.0\nproj_K: [ 1, 2\n  : : ]]\n");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "junk.yml"),
                       "junk.yml:3: cannot parse projector calibration: Missing , between the "
                       "elements");
    writeFile(folder / "junk.xml", "<?xml version=\"1.0\"?>\n<opencv_storage><proj_K>");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "junk.xml"),
                       "junk.xml:2: cannot parse projector calibration: ");
    writeFile(folder / "words.json", "not json at all");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "words.json"),
                       "words.json: cannot parse projector calibration: ");
    // Without the %YAML line the line numbers are still the file's.
    writeFile(folder / "bare.yml", "proj_width: 10\nproj_K: [ 1, 2\n  : : ]]\n");
    EXPECT_INPUT_ERROR(readProjectorCalibration(folder / "bare.yml"),
                       "bare.yml:3: cannot parse projector calibration: ");
}

TEST(ProjectorCalibration, ReadsYamlWithoutItsDirectiveLine) {
    TemporaryFolder folder;
    std::string text = yamlWith("", "");
    text = text.substr(text.find("---\n") + 4);
    writeFile(folder / "bare.yaml", text);
    EXPECT_EQ(readProjectorCalibration(folder / "bare.yaml").height, 1080);
    // Plain lists of numbers are accepted for matrices.
    writeFile(folder / "lists.yml",
              "proj_width: 640\nproj_height: 480\nproj_K: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]\n"
              "R: [0, 0, 0]\nT: [0, 0, 1]\n");
    const ProjectorCalibration c = readProjectorCalibration(folder / "lists.yml");
    EXPECT_EQ(c.K[0], 500);
    EXPECT_EQ(c.R[0], 1);
    EXPECT_EQ(c.T[2], 1);
}

TEST(ProjectorCalibration, DemoProjectorFramesTheVase) {
    const ProjectorCalibration c = makeDemoProjector(0.8);
    EXPECT_EQ(c.width, 1920);
    EXPECT_EQ(c.height, 1080);
    // 30° vertical field of view.
    EXPECT_NEAR(2 * std::atan(0.5 * c.height / c.K[4]) * 180 / M_PI, 30.0, 1e-9);
    const Vec3d centre = c.center();
    EXPECT_NEAR(centre.x, 0, 1e-15);
    EXPECT_NEAR(centre.y, 0.075, 1e-15);
    EXPECT_NEAR(centre.z, 0.8, 1e-15);
    const auto middle = projectToPixel(c, {0, 0.075, 0});
    ASSERT_TRUE(middle);
    EXPECT_NEAR(middle->x, 959.5, 1e-9);
    EXPECT_NEAR(middle->y, 539.5, 1e-9);
    // The lip is above the middle on the image (rows grow downwards); right is right.
    EXPECT_LT(projectToPixel(c, {0, 0.15, 0.04})->y, 539.5);
    EXPECT_GT(projectToPixel(c, {0.05, 0.075, 0})->x, 959.5);
    const ScreenMesh vase = makeProceduralVase();
    for (const Vec3f& p : vase.positions) {
        const auto pixel = projectToPixel(
            c, {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)});
        ASSERT_TRUE(pixel);
        EXPECT_GT(pixel->x, 0);
        EXPECT_LT(pixel->x, c.width - 1);
        EXPECT_GT(pixel->y, 0);
        EXPECT_LT(pixel->y, c.height - 1);
    }
    EXPECT_FALSE(projectToPixel(c, {0, 0.075, 2.0}));  // behind the projector
}

TEST(ProjectorCalibration, ProjectionAppliesOpenCvDistortion) {
    ProjectorCalibration c = makeDemoProjector(1.0, {0, 0, 0});
    c.distortion = {0.1, 0, 0, 0, 0};
    // Point at normalized (0.1, 0) (x right in the image is +x in the world here):
    // r² = 0.01, radial 1.001.
    const auto pixel = projectToPixel(c, {0.1, 0, 0});
    ASSERT_TRUE(pixel);
    EXPECT_NEAR(pixel->x, c.K[2] + c.K[0] * 0.1 * 1.001, 1e-9);
}

// ----------------------------------------------------------------------------------------
// Projector response

TEST(ResponseInput, GammaInverseUndoesTheResponse) {
    const ResponseInput response = ResponseInput::gamma({2.2, 2.4, 1.8});
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i <= 100; ++i) {
            const double x = i / 100.0;
            EXPECT_NEAR(response.level(c, response.output(c, x)), x, 1e-12);
        }
    }
    EXPECT_NEAR(response.output(0, 0.5), std::pow(0.5, 2.2), 1e-15);
    EXPECT_EQ(response.level(0, -0.5), 0.0);
    EXPECT_EQ(response.level(0, 1.5), 1.0);
    EXPECT_EQ(response.level(0, std::nan("")), 0.0);
    EXPECT_EQ(response.output(1, 2.0), 1.0);
}

TEST(ResponseInput, SampledInverseUndoesTheResponseAndClamps) {
    // In cd/m², with a black level: normalized per channel.
    const ResponseInput response = ResponseInput::sampled(
        {0, 0.25, 0.5, 0.75, 1}, {{{2, 10, 40, 90, 200}, {1, 5, 20, 45, 100}, {0, 1, 2, 3, 4}}});
    EXPECT_NEAR(response.output(0, 1), 1.0, 1e-15);
    EXPECT_NEAR(response.output(0, 0), 0.01, 1e-15);
    EXPECT_NEAR(response.output(2, 0.625), 0.625, 1e-15);
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i <= 200; ++i) {
            const double x = i / 200.0;
            EXPECT_NEAR(response.level(c, response.output(c, x)), x, 1e-12) << c << " " << x;
        }
    }
    EXPECT_EQ(response.level(0, 0.005), 0.0);  // below the black level
    EXPECT_EQ(response.level(0, 2.0), 1.0);
    const auto rgb = response.level(response.output({0.3, 0.6, 0.9}));
    EXPECT_NEAR(rgb[0], 0.3, 1e-12);
    EXPECT_NEAR(rgb[1], 0.6, 1e-12);
    EXPECT_NEAR(rgb[2], 0.9, 1e-12);
}

TEST(ResponseInput, FlatStretchesInvertToTheirLowestLevel) {
    const ResponseInput response = ResponseInput::sampled(
        {0, 0.5, 0.8, 1}, {{{0, 0.5, 1, 1}, {0, 0.5, 0.5, 1}, {0, 0.5, 0.5, 1}}});
    EXPECT_DOUBLE_EQ(response.level(0, 1.0), 0.8);  // saturates before level 1
    EXPECT_DOUBLE_EQ(response.level(1, 0.5), 0.5);
    EXPECT_DOUBLE_EQ(response.level(1, 0.75), 0.9);
}

TEST(ResponseInput, ReadsCsvWithHeaderAndComments) {
    TemporaryFolder folder;
    writeFile(folder / "response.csv",
              "\xEF\xBB\xBFlevel,r,g,b\r\n# measured 2024\r\n0, 0.01, 0.01, 0.02\r\n\r\n"
              "0.5,0.2,0.21,0.22\r\n1,1,1,1\r\n");
    const ResponseInput response = readProjectorResponseCsv(folder / "response.csv");
    EXPECT_FALSE(response.isGamma());
    EXPECT_NEAR(response.output(0, 0.25), 0.105, 1e-12);
    EXPECT_NEAR(response.level(2, 0.22), 0.5, 1e-12);
    const ResponseInput same = parseProjectorResponse((folder / "response.csv").string());
    EXPECT_NEAR(same.output(1, 0.75), 0.605, 1e-12);
}

TEST(ResponseInput, CsvErrorsNameTheLine) {
    TemporaryFolder folder;
    const auto refuse = [&](const std::string& text, const std::string& fragment) {
        SCOPED_TRACE(text);
        writeFile(folder / "r.csv", text);
        EXPECT_INPUT_ERROR(readProjectorResponseCsv(folder / "r.csv"), "r.csv" + fragment);
    };
    refuse("level,r,g,b\n0,0,0,0\n0.5,0.6,0.4,0.4\n0.7,0.5,0.6,0.6\n1,1,1,1\n",
           ":4: r output 0.5 is below the previous 0.6: the response must be monotone "
           "non-decreasing");
    refuse("0,0,0,0\n0.5,0.1,0.1,0.1\n0.5,0.2,0.2,0.2\n1,1,1,1\n",
           ":3: level 0.5 does not increase from the previous 0.5");
    refuse("0,0,0,0\n", ": 1 sample; a response curve needs at least 2 (levels 0 and 1)");
    refuse("# nothing\n", ": 0 samples; a response curve needs at least 2");
    refuse("0,0,0,0\n0.5,0.1,zero,0.1\n1,1,1,1\n", ":2: g 'zero' is not a number");
    refuse("0,0,0,0\n0.5,0.1,0.1\n1,1,1,1\n", ":2: expected level,r,g,b (4 numbers), found 3");
    refuse("0,0,0,0\n0.5;0.1;0.1;0.1\n", ":2: expected level,r,g,b (4 numbers), found 1 field");
    refuse("0.1,0,0,0\n1,1,1,1\n", ":1: the first level is 0.1; the curve must start at level 0");
    refuse("0,0,0,0\n0.9,1,1,1\n", ":2: the last level is 0.9; the curve must end at level 1");
    refuse("0,0,0,0\n1,1,1,1.5\n1.5,1,1,2\n", ":3: level 1.5 is outside [0, 1]");
    refuse("0,0,0,-1\n1,1,1,1\n", ":1: b output -1 is not a finite number ≥ 0");
    refuse("0,0,0.3,0\n1,1,0.3,1\n", ": channel g is flat (output 0.3 at every level)");
    refuse("0,0,0,0\n1,1,nan,1\n", ":2: g 'nan' is not a number");
    EXPECT_INPUT_ERROR(readProjectorResponseCsv(folder / "absent.csv"),
                       "absent.csv: cannot open projector response");
}

TEST(ResponseInput, ParsesGammaArguments) {
    EXPECT_TRUE(parseProjectorResponse("2.2").isGamma());
    EXPECT_DOUBLE_EQ(parseProjectorResponse("2.2").exponents()[2], 2.2);
    EXPECT_DOUBLE_EQ(parseProjectorResponse("2.2, 2.3,2.4").exponents()[1], 2.3);
    EXPECT_INPUT_ERROR(parseProjectorResponse("2.2,2.2"), "--response: '2.2,2.2' is neither");
    EXPECT_INPUT_ERROR(parseProjectorResponse("0"), "response: gamma of r is 0");
    EXPECT_INPUT_ERROR(parseProjectorResponse("-1,2,2"), "gamma of r is -1");
    EXPECT_INPUT_ERROR(ResponseInput::gamma(std::nan("")), "gamma of r is nan");
}

// ----------------------------------------------------------------------------------------
// Scene settings

TEST(SceneSettings, DefaultsAreTheDemos) {
    const SceneSettings settings;
    EXPECT_EQ(settings.screenAlbedo, (std::array<double, 3>{0.85, 0.85, 0.85}));
    EXPECT_EQ(settings.ambient, (std::array<double, 3>{0, 0, 0}));
    EXPECT_DOUBLE_EQ(settings.viewer.z, 1.0);
}

TEST(SceneSettings, ParsesTriplesStrictly) {
    const auto p = parsePosition(" 0.1, -2 ,3e-1", "--viewer");
    EXPECT_DOUBLE_EQ(p.x, 0.1);
    EXPECT_DOUBLE_EQ(p.y, -2);
    EXPECT_DOUBLE_EQ(p.z, 0.3);
    for (const char* bad : {"1,2", "1,2,3,4", "1,,3", "a,b,c", "1,2,nan", "", "1 2 3", "1,2,3,",
                            "1,2,inf", "+-1,2,3", "0x1,2,3"}) {
        SCOPED_TRACE(bad);
        EXPECT_INPUT_ERROR(parseTriple(bad, "--viewer"),
                           "--viewer: '" + std::string(bad) +
                               "' is not x,y,z (three finite numbers separated by commas)");
    }
}

TEST(SceneSettings, ParsesAlbedoAndAmbient) {
    EXPECT_EQ(parseAlbedo("0.8", "--albedo"), (std::array<double, 3>{0.8, 0.8, 0.8}));
    EXPECT_EQ(parseAlbedo("0.9,0.8,0.7", "--albedo"), (std::array<double, 3>{0.9, 0.8, 0.7}));
    EXPECT_INPUT_ERROR(parseAlbedo("1.2", "--albedo"),
                       "--albedo: '1.2': each value must be in (0, 1]");
    EXPECT_INPUT_ERROR(parseAlbedo("0,0.5,0.5", "--albedo"), "each value must be in (0, 1]");
    EXPECT_INPUT_ERROR(parseAlbedo("0.5,0.5", "--albedo"),
                       "--albedo: '0.5,0.5' is not a value or r,g,b");
    EXPECT_EQ(parseAmbient("0.02,0.03,0.04", "--ambient"),
              (std::array<double, 3>{0.02, 0.03, 0.04}));
    EXPECT_INPUT_ERROR(parseAmbient("-0.1", "--ambient"),
                       "--ambient: '-0.1': each value must be ≥ 0");
}

}  // namespace
}  // namespace vpe::scene
