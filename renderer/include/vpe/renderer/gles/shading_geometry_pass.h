// SPDX-License-Identifier: MIT
// ShadingGeometryPass: the part of each projector pixel's geometry a frame shades with, packed
// small. Its position less the centre of the object's covered bounding box and 1/S as half
// floats (kPositionFormat, 8 bytes where geometry0 takes 16: about the centre a half float keeps
// 2⁻¹¹ of the distance, 2⁻¹⁰ where the GPU truncates as it writes the target (llvmpipe does):
// 0.5–1 mm at 1 m; 1/S at most 65504, which clips any wanted light above
// 1.5e-5 as kNoProjectorLight does), and the shading normal n, the mirrored viewer m = 2(n·v)n − v
// (mirroredViewer: the viewer is fixed, so cos θs = l·m per frame) and the geometric normal's x, y
// as half floats, two a word, in one RGBA32UI texel (kShadingFormat): one fetch and four unpacks
// where the frame fetched the normal's float bits, decoded an octahedral normal and normalised v.
// The geometric normal's z rides in the material's spare half (materialPassShaderSource). Run at
// load and after each relief pass (the relief tilts n, and with it m).
#pragma once

#include <array>

#include "vpe/renderer/gles/geometry_buffer.h"
#include "vpe/renderer/gles/gl_program.h"
#include "vpe/renderer/gles/tile_cover.h"

namespace vpe::renderer::gles {

class ShadingGeometryPass {
public:
    // Compiles the pass and allocates its target; the geometry and tiles must outlive it.
    ShadingGeometryPass(const GeometryBuffer& geometry, const TileCover& tiles,
                        const std::array<float, 3>& viewer);

    // Packs geometry1 (as traced, or as the relief pass left it) into shading().
    void run();
    const GlObject& shading() const { return shading_; }
    const GlObject& position() const { return position_; }

private:
    const GeometryBuffer& geometry_;
    const TileCover& tiles_;
    std::array<float, 3> viewer_;
    GlObject shading_, position_, program_, framebuffer_;
};

// The pass's fragment shader (for tests and counting).
std::string shadingGeometryShaderSource();

}  // namespace vpe::renderer::gles
