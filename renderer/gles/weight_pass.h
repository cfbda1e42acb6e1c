// SPDX-License-Identifier: MIT
// WeightPass: with live weights, each preset's α per projector pixel — the regions' weight maps
// sampled at the pixel's uv once, at load, instead of every frame: a frame fetches one texel of
// up to four regions' α (alphaFormat) where it fetched the uv and one filtered texel a region.
// The filtering is the shader's own (vpeBilinearWeight, the CPU reference's footprint), so an
// 8-bit preset gives the same α on any GPU.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry_buffer.h"
#include "gl_program.h"
#include "theta_textures.h"
#include "tile_cover.h"

namespace vpe::renderer::gles {

class WeightPass {
public:
    // Compiles the pass and runs it for every preset (a GL ES 3.1 context must be current; the
    // textures, geometry and tiles must outlive the pass).
    WeightPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
               const TileCover& tiles);

    // Preset `preset`'s α: layout().alphaLayers() layers of alphaFormat(regions).
    const GlObject& alpha(std::size_t preset) const { return alpha_[preset]; }

private:
    std::vector<GlObject> alpha_;
};

}  // namespace vpe::renderer::gles
