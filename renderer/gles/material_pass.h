// SPDX-License-Identifier: MIT
// MaterialPass: per projector pixel, the θs material at the pixel's uv — one region alone, or
// a preset's regions blended by its weights — scaled by the viewer's horizon factor (fixed per
// pixel) and coded as material_codes.h says, in projector space. Run once at load and once per
// preset change; a frame then fetches a pixel's material with no filtering and no uv. With live
// weights, the compose pass blends the regions' coded materials by a preset's α per pixel (the
// weight pass's) in projector space, which costs a pass of reads and writes where the material
// pass samples every region's maps in texture space.
#pragma once

#include <array>
#include <vector>

#include "geometry_buffer.h"
#include "gl_program.h"
#include "theta_textures.h"
#include "tile_cover.h"
#include "viewer_eyes.h"

namespace vpe::renderer::gles {

// A coded material in projector space: the u codes, 1/S and g.z (kMaterialFormat,
// layout().materialLayers() layers) and the kd codes (kDiffuseFormat).
struct CodedMaterial {
    GlObject codes, diffuse;
};

class MaterialPass {
public:
    // Compiles the pass's programs (up to four colour attachments a draw: GLES 3.1 guarantees
    // four). The textures, geometry and tiles must outlive the pass.
    MaterialPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
                 const TileCover& tiles, const ViewerEyes& eyes);

    // Textures of the projector's size for one coded material.
    CodedMaterial makeTarget() const;
    // Writes the material of `region` alone into `target`.
    void composeRegion(const CodedMaterial& target, int region);
    // Writes the material of all regions blended by preset `preset`'s weights.
    void composePreset(const CodedMaterial& target, std::size_t preset);
    // Writes the regions' materials (one each, from composeRegion) blended by `alpha` (the weight
    // pass's α of a preset) into `target`.
    void blendRegions(const CodedMaterial& target, const std::vector<CodedMaterial>& regions,
                      const GlObject& alpha);

private:
    // Draws code layers [first, first + count) and, with `diffuse`, the kd codes.
    struct Group {
        int first = 0, count = 0;
        bool diffuse = false;
        GlObject program;
        int region = -1;
    };
    std::vector<Group> groups(bool compose);
    // The sampling pass: `region` alone (≥ 0) or all weighted by `weights`.
    void sample(const CodedMaterial& target, int region, const GlObject* weights);
    void draw(const CodedMaterial& target, const Group& group);

    const ThetaTextures& textures_;
    const GeometryBuffer& geometry_;
    const TileCover& tiles_;
    ViewerEyes eyes_;
    std::vector<Group> sample_, blend_;
    GlObject framebuffer_;
};

}  // namespace vpe::renderer::gles
