// SPDX-License-Identifier: MIT
// What the tests of `vpe bake`'s inputs (scene/: meshes, the vase, projector calibration,
// responses, settings) share: the one-line InputError check, fixture files, mesh comparisons.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "vpe/common/input_error.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::scene::test {

// The message of the InputError `f` throws; fails the test when it throws none.
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const common::InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "no InputError thrown";
    return {};
}

#define EXPECT_INPUT_ERROR(statement, fragment)                                               \
    do {                                                                                      \
        const std::string message_ = ::vpe::scene::test::errorOf([&] { (void)(statement); }); \
        EXPECT_NE(message_.find(fragment), std::string::npos) << message_;                    \
        EXPECT_EQ(message_.find('\n'), std::string::npos) << "not one line: " << message_;    \
    } while (false)

inline void writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream stream(path, std::ios::binary);
    stream << text;
}

inline double distance(const Vec3f& a, const Vec3f& b) {
    const double dx = static_cast<double>(a.x) - static_cast<double>(b.x);
    const double dy = static_cast<double>(a.y) - static_cast<double>(b.y);
    const double dz = static_cast<double>(a.z) - static_cast<double>(b.z);
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

inline Vec3f faceNormal(const ScreenMesh& mesh, std::size_t t) {
    const Vec3f a = mesh.positions[mesh.indices[3 * t]];
    const Vec3f b = mesh.positions[mesh.indices[3 * t + 1]];
    const Vec3f c = mesh.positions[mesh.indices[3 * t + 2]];
    const Vec3f e1{b.x - a.x, b.y - a.y, b.z - a.z}, e2{c.x - a.x, c.y - a.y, c.z - a.z};
    return {e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
}

// Every corner of every triangle of `actual` matches `expected` (same triangle order, as the
// loader keeps the file's face order).
inline void expectSameTriangles(const ScreenMesh& expected, const ScreenMesh& actual) {
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
inline constexpr const char* kSquareObj =
    "# a square\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3 4/4\n";  // a quad: triangulated on load

}  // namespace vpe::scene::test
