// SPDX-License-Identifier: MIT
// Scenes made by code for the CPU renderer's tests: owned meshes and materials with views.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/material_textures.h"
#include "vpe/renderer/cpu/render_mesh.h"

namespace vpe::renderer::testing {

struct OwnedMesh {
    std::vector<Vec3f> positions, normals;
    std::vector<Vec2f> uvs;
    std::vector<std::uint32_t> indices;

    RenderMesh view() const { return {positions, normals, uvs, indices}; }
};

// The square [−halfSize, halfSize]² of the plane z = depth, cells × cells quads, normals
// (0, 0, −1) (facing a projector at the origin looking along +z); u = (x + halfSize) /
// (2·halfSize), v = (y + halfSize) / (2·halfSize).
OwnedMesh makePlaneMesh(double depth, double halfSize, int cells);

// A width × height pinhole at the origin looking along +z (R = I, T = 0, no distortion), focal
// length `focal` pixels, its principal point at the image's centre: the one those planes face.
proto::PinholeCamera centredPinhole(int width, int height, double focal);

// A vase-like surface of revolution about the y axis: radius r(y) = 0.05 + 0.015·sin(2π·y /
// 0.15) + 0.01·y/0.15 for y ∈ [0, 0.15] m, open at both ends; `segments` around, `rings`
// along; exact outward normals; u = φ/2π (seam duplicated, u = 0.5 faces +z), v = y / 0.15.
OwnedMesh makeVaseMesh(int segments, int rings);
double vaseRadius(double y);

// A material map whose coefficient k of channel c at texel (x, y) is value(x, y, k, c).
struct OwnedMaterial {
    int harmonics = 0, width = 0, height = 0;
    std::vector<std::vector<float>> coefficients, weights;  // per region

    MaterialTextures view() const;
};

using CoefficientFunction = std::function<double(int x, int y, int k, int c)>;
OwnedMaterial makeMaterial(int harmonics, int width, int height, const CoefficientFunction& value);
// Adds a region with its weight map; weights of all regions must add up to 1 (the caller's
// business).
void addRegion(OwnedMaterial& material, const CoefficientFunction& value,
               const std::function<double(int x, int y)>& weight);

}  // namespace vpe::renderer::testing
