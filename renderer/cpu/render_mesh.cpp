// SPDX-License-Identifier: MIT
// checkRenderMesh.
#include "vpe/renderer/cpu/render_mesh.h"

#include <cmath>

namespace vpe::renderer {

std::string checkRenderMesh(const RenderMesh& mesh) {
    const std::size_t vertices = mesh.positions.size();
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
        return "indices: " + std::to_string(mesh.indices.size()) +
               " values, expected a positive multiple of 3";
    }
    if (mesh.normals.size() != vertices) {
        return "normals: " + std::to_string(mesh.normals.size()) + " values, expected " +
               std::to_string(vertices);
    }
    if (mesh.uvs.size() != vertices) {
        return "uvs: " + std::to_string(mesh.uvs.size()) + " values, expected " +
               std::to_string(vertices);
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= vertices) {
            return "indices: value " + std::to_string(i) + " is " +
                   std::to_string(mesh.indices[i]) + ", not below the vertex count " +
                   std::to_string(vertices);
        }
    }
    for (std::size_t i = 0; i < vertices; ++i) {
        const Vec3f& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return "positions: vertex " + std::to_string(i) + " is not finite";
        }
    }
    return "";
}

}  // namespace vpe::renderer
