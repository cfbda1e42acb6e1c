// SPDX-License-Identifier: MIT
// GeometryBuffer: the per-projector-pixel geometry (renderer::ProjectorPixels, the CPU
// reference's own definition: exact rays in double precision) packed and uploaded once per
// bundle and projector. A frame only fetches it: no ray is cast and no triangle is read per
// frame (Pellacini's deep framebuffer; Bimber's precomputed projector form factor).
//
// Three textures, texel (x, y) = projector pixel (x, y), row 0 the projector's top row:
//   geometry0 RGBA32F: X (object frame, metres) and s/S (S the projector's irradiance scale
//     P·cos θp/d², s its share of the light among several projectors, 1 alone: the inverse of
//     ProjectorPixel::compensationScale), at most kNoProjectorLight (S = 0: any light asked of
//     the projector there clips, none gives 0, as compensatePixel's ±∞), 0 where s = 0,
//     kUncovered when the pixel sees nothing;
//   geometry1 RGBA32UI: the shading normal's float bits (xyz), the geometric normal (w,
//     encodeOctahedralNormal: it only decides the horizon);
//   uv RG32F: the texture coordinate, rows from the top as the bundle stores it (read by the
//     material pass, and by frames with live weights; floats, as unpacking 16-bit unorms
//     costs V3D six operations a pixel).
// With a relief (a bundle carrying detail normal maps), geometry1 is what the relief pass
// writes — the shading normal tilted by the preset's relief — and two more textures, read only
// by that pass, keep what it starts from:
//   tracedGeometry1 RGBA32UI: geometry1 as traced (the mesh's shading normal);
//   tangents RG32UI: the relief's tangent frame, t and b (proto::tangentFrame of the shading
//     normal and the triangle's ∂X/∂u, ∂X/∂v), octahedral.
// Full floats where the shading's precision needs them: unpacking costs ALU, which the Pi's
// GPU has least of (docs/pi-headroom.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "vpe/renderer/cpu/projector_pixels.h"

#include "gl_program.h"

namespace vpe::renderer::gles {

inline constexpr float kNoProjectorLight = 1e30f;
inline constexpr float kUncovered = -1.0f;

// One pixel as packed (the CPU side of what the shaders unpack; for tests).
struct PackedPixel {
    std::array<float, 4> geometry0{0, 0, 0, kUncovered};
    std::array<std::uint32_t, 4> geometry1{0, 0, 0, 0};
    std::array<float, 2> uv{0, 0};
    std::array<std::uint32_t, 2> tangents{0, 0};
};
PackedPixel packProjectorPixel(const std::optional<ProjectorPixel>& pixel);

class GeometryBuffer {
public:
    // Traces every pixel (threads ≤ 0: all cores) in bands of rows, each band packed and
    // uploaded before the next is traced, so the CPU never holds the whole buffer. A GL ES 3.1
    // context must be current.
    GeometryBuffer(const ProjectorPixels& pixels, int threads = 0, bool relief = false);

    const GlObject& geometry0() const { return geometry0_; }
    const GlObject& geometry1() const { return geometry1_; }
    const GlObject& uv() const { return uv_; }
    bool relief() const { return relief_; }
    // With a relief only (empty objects otherwise).
    const GlObject& tracedGeometry1() const { return tracedGeometry1_; }
    const GlObject& tangents() const { return tangents_; }
    int width() const { return width_; }
    int height() const { return height_; }
    std::size_t coveredPixels() const { return covered_; }
    // The cube the covered pixels' positions lie in (object frame, metres): its low corner and
    // side, the bounding box's longest. The frame's positions are 10-bit fractions of it
    // (ShadingGeometryPass).
    struct Cube {
        std::array<double, 3> low{0, 0, 0};
        double side = 1;
    };
    const Cube& cube() const { return cube_; }
    // Per kTileSize × kTileSize tile (tile_cover.h), row-major: whether a pixel sees the object.
    const std::vector<std::uint8_t>& coveredTiles() const { return coveredTiles_; }

private:
    int width_ = 0, height_ = 0;
    bool relief_ = false;
    std::size_t covered_ = 0;
    Cube cube_;
    std::vector<std::uint8_t> coveredTiles_;
    GlObject geometry0_, geometry1_, uv_, tracedGeometry1_, tangents_;
};

}  // namespace vpe::renderer::gles
