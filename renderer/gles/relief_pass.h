// SPDX-License-Identifier: MIT
// ReliefPass: a bundle's relief (format 1.2: detail normal maps, proto/detail_normal.h) folded
// into the geometry buffer's shading normal — at load and when the preset changes, never per
// frame: a frame reads geometry1 as it does without a relief, at the same cost. Per projector
// pixel it blends the regions' detail normals at the pixel's uv by the preset's weights (as the
// material pass blends their coefficients) and tilts the traced shading normal through the
// pixel's tangent frame (renderer::shadingNormal, the CPU reference's definition).
#pragma once

#include <cstddef>

#include "vpe/proto/bundle.h"

#include "frame_shaders.h"
#include "geometry_buffer.h"
#include "gl_program.h"
#include "theta_textures.h"
#include "tile_cover.h"

namespace vpe::renderer::gles {

class ReliefPass {
public:
    // Whether any of the bundle's regions carries a relief map.
    static bool needed(const proto::BundleView& bundle);

    // Uploads the regions' detail normals (RG16F, one layer per region, (0, 0) for a region
    // without) and compiles the pass. The geometry buffer must have been built with its relief
    // textures; it, the textures and the tiles must outlive the pass.
    ReliefPass(const proto::BundleView& bundle, GeometryBuffer& geometry,
               const ThetaTextures& textures, const TileCover& tiles);

    // Writes geometry1 with the relief of `region` alone, or of the preset's blend.
    void composeRegion(int region);
    void composePreset(std::size_t preset);

private:
    void run(int region, const GlObject* weights);

    GeometryBuffer& geometry_;
    const ThetaTextures& textures_;
    const TileCover& tiles_;
    GlObject detail_, program_, framebuffer_;
    int regionUniform_ = -1;
};

}  // namespace vpe::renderer::gles
