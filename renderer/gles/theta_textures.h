// SPDX-License-Identifier: MIT
// ThetaTextures: a bundle's material as the GLES renderer samples it at load — every region's
// coefficient map re-expressed in the θs basis (renderer::thetaMaterialMap) as an RGBA16F array
// in texture space, the presets' weight maps, the coding that covers the maps, and the θs table
// h_j(x) scaled for the coded material.
#pragma once

#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/proto/theta_basis.h"

#include "frame_shaders.h"
#include "gl_program.h"
#include "material_codes.h"

namespace vpe::renderer::gles {

class ThetaTextures {
public:
    // A GL ES 3.1 context must be current. Throws GraphicsError when the textures exceed
    // maxSize or GL_MAX_ARRAY_TEXTURE_LAYERS.
    ThetaTextures(const proto::BundleView& bundle, const proto::ThetaBasis& basis, int tableSamples,
                  int maxSize);

    const ShaderLayout& layout() const { return layout_; }
    const GlObject& map(std::size_t region) const { return maps_[region]; }
    // One α layer per region; none when the bundle has no presets (a single region).
    const GlObject& weights(std::size_t preset) const { return weights_[preset]; }
    std::size_t presetCount() const { return weights_.size(); }
    // h_j(x)·step_j/unit (scaledThetaTable), which a frame multiplies the u codes by.
    const GlObject& table() const { return table_; }
    // How the projector-space materials are coded: covers every region's map.
    const MaterialCoding& coding() const { return coding_; }

private:
    ShaderLayout layout_;
    std::vector<GlObject> maps_, weights_;
    GlObject table_;
    MaterialCoding coding_;
};

}  // namespace vpe::renderer::gles
