// SPDX-License-Identifier: MIT
// Screen meshes (OBJ, PLY): round trips, generated normals, units, and every refusal with its
// one-line message.
#include "vpe/scene/screen_mesh.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/scene/procedural_vase.h"

#include "offline/scene/scene_test_support.h"
#include "support/test_data.h"

namespace vpe::scene {
namespace {

using namespace test;  // NOLINT: the shared helpers of scene_test_support.h
using testing::TemporaryFolder;

// The mesh loaded back from `path` has every corner of `written`.
void expectLoadsAs(const ScreenMesh& written, const std::filesystem::path& path) {
    const ScreenMesh loaded = loadScreenMesh(path);
    EXPECT_EQ(loaded.vertexCount(), written.vertexCount());
    expectSameTriangles(written, loaded);
}

// The mesh in `text`, written to `name` in `folder` and loaded: for the refusals.
ScreenMesh loadWritten(const TemporaryFolder& folder, const std::string& name,
                       const std::string& text) {
    writeFile(folder / name, text);
    return loadScreenMesh(folder / name);
}

// A square, as kSquareObj has it: two triangles on four corners.
void expectTwoTrianglesOnFourCorners(const ScreenMesh& mesh) {
    EXPECT_EQ(mesh.triangleCount(), 2u);
    EXPECT_EQ(mesh.vertexCount(), 4u);
}

TEST(ScreenMesh, ObjRoundTripKeepsEveryCorner) {
    TemporaryFolder folder;
    const ScreenMesh vase = makeProceduralVase({.segments = 12, .rings = 6, .baseRings = 2});
    writeScreenMeshObj(vase, folder / "vase.obj");
    expectLoadsAs(vase, folder / "vase.obj");
    // Nothing but the file is left behind (the write was atomic).
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder.path()), {}), 1);
}

TEST(ScreenMesh, ObjQuadsAreTriangulatedAndNormalsGenerated) {
    TemporaryFolder folder;
    writeFile(folder / "square.obj", kSquareObj);
    const ScreenMesh mesh = loadScreenMesh(folder / "square.obj");
    expectTwoTrianglesOnFourCorners(mesh);
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
    const ScreenMesh vase = makeProceduralVase({.segments = 10, .rings = 5, .baseRings = 2});
    writeBinaryPly(vase, folder / "vase.ply");
    expectLoadsAs(vase, folder / "vase.ply");
}

TEST(ScreenMesh, AsciiPlyWithoutNormalsGetsSmoothNormals) {
    TemporaryFolder folder;
    writeFile(folder / "square.ply", plyHeader("ascii", 4, 2, false) +
                                         "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n"
                                         "3 0 1 2\n3 0 2 3\n");
    const ScreenMesh mesh = loadScreenMesh(folder / "square.ply");
    expectTwoTrianglesOnFourCorners(mesh);
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
    expectTwoTrianglesOnFourCorners(mesh);
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
    EXPECT_INPUT_ERROR(loadWritten(folder, "square.stl", "solid x\nendsolid x\n"),
                       "square.stl: unsupported mesh format '.stl' (vpe reads .obj and .ply)");
}

TEST(ScreenMesh, RefusesUnparsableFiles) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(loadWritten(folder, "broken.ply",
                                   "ply\nformat ascii 1.0\nelement vertex banana\nend_header\n"),
                       "broken.ply: cannot parse mesh");
    EXPECT_INPUT_ERROR(loadWritten(folder, "empty.obj", ""), "empty.obj: cannot parse mesh");
}

TEST(ScreenMesh, RefusesFilesWithoutTriangles) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(
        loadWritten(folder, "lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nl 1 2\nl 2 3\n"),
        "lines.obj: no triangles: a screen mesh needs faces, not only points or lines");
    EXPECT_INPUT_ERROR(
        loadWritten(folder, "cloud.ply",
                    plyHeader("ascii", 3, 0, false) + "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n"),
        "cloud.ply: no triangles");
    EXPECT_INPUT_ERROR(loadWritten(folder, "text.obj", "this is not a mesh\n"),
                       "text.obj: no triangles");
}

TEST(ScreenMesh, RefusesMeshesWithoutUvs) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(loadWritten(folder, "plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n"),
                       "plain.obj: no texture coordinates: a screen mesh needs UVs");
}

TEST(ScreenMesh, RefusesNonFinitePositions) {
    TemporaryFolder folder;
    const ScreenMesh vase = makeProceduralVase({.segments = 6, .rings = 2, .baseRings = 1});
    writeBinaryPly(vase, folder / "nan.ply", 7, std::nanf(""));
    EXPECT_INPUT_ERROR(loadScreenMesh(folder / "nan.ply"),
                       "nan.ply: a vertex has a position that is not a finite number");
    EXPECT_INPUT_ERROR(
        loadWritten(folder, "nan.obj", "v 0 0 0\nv 1 nan 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"),
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
    EXPECT_INPUT_ERROR(
        loadWritten(folder, "tiled.obj",
                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 2 0\nvt 2 1\nf 1/1 2/2 3/3\n"),
        "has texture coordinates (2, 0) outside [0, 1]; vpe does not wrap");
}

TEST(ScreenMesh, RefusesMeshesOfOnlyDegenerateTriangles) {
    TemporaryFolder folder;
    EXPECT_INPUT_ERROR(
        loadWritten(folder, "flat.obj",
                    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nvt 0 0\nf 1/1 2/1 3/1\nf 2/1 3/1 4/1\n"),
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

}  // namespace
}  // namespace vpe::scene
