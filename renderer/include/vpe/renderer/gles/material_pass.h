// SPDX-License-Identifier: MIT
// MaterialPass: per projector pixel, the θs material at the pixel's uv — one region alone, or
// a preset's regions blended by its weights — scaled by the viewer's horizon factor (fixed per
// pixel) and packed as half floats into an RGBA32UI texture array in projector space. Run once
// at load and once per preset change; a frame then fetches a pixel's material with no
// filtering and no uv.
#pragma once

#include <array>
#include <vector>

#include "vpe/renderer/gles/geometry_buffer.h"
#include "vpe/renderer/gles/gl_program.h"
#include "vpe/renderer/gles/theta_textures.h"
#include "vpe/renderer/gles/tile_cover.h"

namespace vpe::renderer::gles {

class MaterialPass {
public:
    // Compiles the pass's programs (up to four packed layers per draw, one colour attachment
    // each: GLES 3.1 guarantees four). Both objects must outlive the pass.
    MaterialPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
                 const TileCover& tiles, const std::array<float, 3>& viewer);

    // An RGBA32UI array of the projector's size with layout().materialLayers() layers.
    GlObject makeTarget() const;
    // Writes the material of `region` alone into `target`.
    void composeRegion(const GlObject& target, int region);
    // Writes the material of all regions blended by preset `preset`'s weights.
    void composePreset(const GlObject& target, std::size_t preset);

private:
    void run(const GlObject& target, int region, const GlObject* weights);

    const ThetaTextures& textures_;
    const GeometryBuffer& geometry_;
    const TileCover& tiles_;
    std::array<float, 3> viewer_;
    struct Group {
        int first = 0, count = 0;
        GlObject program;
        int region = -1, viewer = -1;
    };
    std::vector<Group> groups_;
    GlObject framebuffer_;
};

}  // namespace vpe::renderer::gles
