// SPDX-License-Identifier: MIT
// RenderMesh: the screen object as the renderer takes it — views of caller-owned arrays
// (a mapped bundle, or vectors), never copied; they must outlive the render call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer {

// Object frame, metres. One normal and one texture coordinate per position; normals need not
// be unit length (the renderer normalizes the interpolated normal). Texture coordinates
// follow OBJ / OpenGL: (0, 0) is the BOTTOM-left corner of the textures, v grows upwards.
// Triangles may wind either way: the side a ray hits is found from the geometry (see
// surface_point.h).
struct RenderMesh {
    std::span<const Vec3f> positions;
    std::span<const Vec3f> normals;
    std::span<const Vec2f> uvs;
    std::span<const std::uint32_t> indices;  // three per triangle

    std::size_t triangleCount() const { return indices.size() / 3; }
};

// Why the mesh cannot be rendered, as a phrase ("normals: 3 values, expected 4"); "" when it
// can: at least one triangle, indices a multiple of 3 and < the vertex count, one normal and
// one uv per position, positions finite.
std::string checkRenderMesh(const RenderMesh& mesh);

}  // namespace vpe::renderer
