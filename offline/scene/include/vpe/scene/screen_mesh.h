// SPDX-License-Identifier: MIT
// ScreenMesh: the white object the projector paints, as `vpe bake` takes it — an indexed
// triangle mesh in metres in the object's own frame, with a normal and a texture coordinate
// per vertex. Read from OBJ or PLY (through assimp) and written as OBJ.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/proto/vector_types.h"

namespace vpe::scene {

using Vec2f = proto::Vec2f;
using Vec3f = proto::Vec3f;

// Texture coordinates follow OBJ and OpenGL: (0, 0) is the bottom-left corner of the screen
// texture, v grows upwards; all lie in [0, 1] (no wrapping). Triangles are counter-clockwise
// seen from outside, normals unit length and outward.
struct ScreenMesh {
    std::vector<Vec3f> positions;        // metres, object frame
    std::vector<Vec3f> normals;          // one per position
    std::vector<Vec2f> uvs;              // one per position
    std::vector<std::uint32_t> indices;  // three per triangle

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return indices.size() / 3; }
};

struct ScreenMeshLoadOptions {
    // Scale from the file's length unit to metres (1000-unit scans in millimetres: 0.001).
    double metresPerUnit = 1.0;
};

// How far texture coordinates may stray outside [0, 1] (exporters' rounding) before the mesh
// is refused; those within are clamped.
inline constexpr float kUvTolerance = 1e-3f;

// Reads an OBJ or PLY file: triangulated, identical vertices joined, smooth normals
// generated when the file has none, triangles of zero area dropped. Throws InputError
// "PATH: problem" when the file is missing or unparsable, has no triangles or no texture
// coordinates, positions that are not finite, coordinates outside [0, 1], more vertices than
// 32-bit indices reach, or only degenerate triangles.
ScreenMesh loadScreenMesh(const std::filesystem::path& path,
                          const ScreenMeshLoadOptions& options = {});

// Writes the mesh as a Wavefront OBJ (v, vt, vn, f a/a/a), shortest round-tripping decimals,
// atomically.
void writeScreenMeshObj(const ScreenMesh& mesh, const std::filesystem::path& path);

// The checks loadScreenMesh makes, for meshes made in memory; `source` names the mesh in
// messages. Clamps coordinates within kUvTolerance and renormalizes normals in place.
void validateScreenMesh(ScreenMesh& mesh, const std::filesystem::path& source);

// Throws InputError when `count` vertices cannot be addressed by 32-bit indices: at most
// 2³² − 1, as index 0xFFFFFFFF is GL's primitive-restart index.
void requireIndexableVertexCount(std::uint64_t count, const std::filesystem::path& source);

}  // namespace vpe::scene
