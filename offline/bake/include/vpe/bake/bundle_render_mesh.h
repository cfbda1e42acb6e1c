// SPDX-License-Identifier: MIT
// BundleRenderMesh: a bundle's mesh as the renderer takes it (its uv with v up, as OBJ and GL
// have it; the bundle stores rows from the top), owning the arrays its view points into. What
// the bake traces projector pixels on: the measured light's maps, a show's blend.
#pragma once

#include <vector>

#include "vpe/bake/bundle_writer.h"
#include "vpe/renderer/cpu/render_mesh.h"

namespace vpe::bake {

struct BundleRenderMesh {
    std::vector<renderer::Vec3f> positions, normals;
    std::vector<renderer::Vec2f> uvs;
    renderer::RenderMesh view;

    explicit BundleRenderMesh(const BundleMesh& mesh) {
        for (std::size_t v = 0; 3 * v < mesh.positions.size(); ++v) {
            positions.push_back(
                {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
            normals.push_back(
                {mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]});
            uvs.push_back({mesh.uvs[2 * v], 1.0f - mesh.uvs[2 * v + 1]});
        }
        view = {positions, normals, uvs, mesh.indices};
    }
    BundleRenderMesh(const BundleRenderMesh&) = delete;  // the view points into the arrays
    BundleRenderMesh& operator=(const BundleRenderMesh&) = delete;
};

}  // namespace vpe::bake
