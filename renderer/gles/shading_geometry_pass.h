// SPDX-License-Identifier: MIT
// ShadingGeometryPass: the part of each projector pixel's geometry a frame shades with, packed
// small. Its position as 10-bit fractions of the object's cube (GeometryBuffer::cube) in an
// RGB10_A2 texel, alpha 1 where the pixel sees the object (kPositionFormat: 4 bytes, decoded by
// the texture unit; a step is 1/1023 of the cube's side, ±0.7 mm on a 1.4 m object at most,
// 0.05° of the light's direction at 1 m), and the shading normal n, the mirrored viewer
// m = 2(n·v)n − v (mirroredViewer: the viewer is fixed, so cos θs = l·m per frame) and the
// geometric normal's x, y as half floats, two a word, in one RGBA32UI texel (kShadingFormat).
// 1/S and the geometric normal's z ride in the material's codes (material_codes.h). Run at load
// and after each relief pass (the relief tilts n, and with it m).
#pragma once

#include <array>

#include "geometry_buffer.h"
#include "gl_program.h"
#include "tile_cover.h"
#include "viewer_eyes.h"

namespace vpe::renderer::gles {

class ShadingGeometryPass {
public:
    // Compiles the pass and allocates its target; the geometry and tiles must outlive it.
    ShadingGeometryPass(const GeometryBuffer& geometry, const TileCover& tiles,
                        const ViewerEyes& eyes);

    // Packs geometry1 (as traced, or as the relief pass left it) into shading().
    void run();
    const GlObject& shading() const { return shading_; }
    const GlObject& position() const { return position_; }

private:
    const GeometryBuffer& geometry_;
    const TileCover& tiles_;
    ViewerEyes eyes_;
    GlObject shading_, position_, program_, framebuffer_;
};

// The pass's fragment shader (for tests and counting).
std::string shadingGeometryShaderSource();

}  // namespace vpe::renderer::gles
