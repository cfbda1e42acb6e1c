// SPDX-License-Identifier: MIT
// MaterialPass: compose projector-space materials (see the header).
#include "vpe/renderer/gles/material_pass.h"

#include <algorithm>
#include <string>
#include <vector>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"
#include "vpe/renderer/gles/texture_formats.h"

namespace vpe::renderer::gles {

namespace {

// Texture units of the pass: geometry 0–1, uv 2, weights 3, the regions' maps from 4.
constexpr int kUnitGeometry0 = 0, kUnitGeometry1 = 1, kUnitUv = 2, kUnitWeights = 3, kUnitMaps = 4;
constexpr int kMaxAttachments = 4;  // GL_MAX_DRAW_BUFFERS in GLES 3.1 is at least 4

void bind(int unit, GLenum kind, unsigned texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
    glBindTexture(kind, texture);
}

}  // namespace

MaterialPass::MaterialPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
                           const TileCover& tiles, const std::array<float, 3>& viewer)
    : textures_(textures), geometry_(geometry), tiles_(tiles), viewer_(viewer) {
    const ShaderLayout& layout = textures.layout();
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    if (kUnitMaps + layout.regions > units) {
        throw GraphicsError(std::to_string(layout.regions) +
                            " regions need more texture units than the " + std::to_string(units) +
                            " the GPU has (at most " + std::to_string(units - kUnitMaps) + ")");
    }
    for (int first = 0; first < layout.materialLayers(); first += kMaxAttachments) {
        Group group;
        group.first = first;
        group.count = std::min(kMaxAttachments, layout.materialLayers() - first);
        const std::string name = "material" + std::to_string(first) + ".frag";
        const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
        unsigned fragment = 0;
        try {
            fragment = compileShader(GL_FRAGMENT_SHADER, name,
                                     materialPassShaderSource(layout, first, group.count));
        } catch (...) {
            glDeleteShader(vertex);
            throw;
        }
        group.program = GlObject::program(linkProgram(name, vertex, fragment));
        const GLuint program = group.program.get();
        glUseProgram(program);
        glUniform1i(glGetUniformLocation(program, "uGeometry0"), kUnitGeometry0);
        glUniform1i(glGetUniformLocation(program, "uGeometry1"), kUnitGeometry1);
        glUniform1i(glGetUniformLocation(program, "uUv"), kUnitUv);
        glUniform1i(glGetUniformLocation(program, "uWeights"), kUnitWeights);
        for (int r = 0; r < layout.regions; ++r) {
            glUniform1i(glGetUniformLocation(program, ("uThetaMap" + std::to_string(r)).c_str()),
                        kUnitMaps + r);
        }
        // The material textures' rows are the projector's, top row first.
        glUniform1i(glGetUniformLocation(program, "uTopRowAtOrigin"), 1);
        glUniform2f(glGetUniformLocation(program, "uSize"), static_cast<float>(geometry.width()),
                    static_cast<float>(geometry.height()));
        group.region = glGetUniformLocation(program, "uRegion");
        group.viewer = glGetUniformLocation(program, "uViewer");
        groups_.push_back(std::move(group));
    }
    framebuffer_ = GlObject::framebuffer();
    checkGlError("building the material pass");
}

GlObject MaterialPass::makeTarget() const {
    return makeArrayTexture(kMaterialFormat, geometry_.width(), geometry_.height(),
                            textures_.layout().materialLayers(), GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                            nullptr, TextureFilter::kNearest);
}

void MaterialPass::composeRegion(const GlObject& target, int region) {
    run(target, region, nullptr);
}

void MaterialPass::composePreset(const GlObject& target, std::size_t preset) {
    run(target, -1, &textures_.weights(preset));
}

void MaterialPass::run(const GlObject& target, int region, const GlObject* weights) {
    bind(kUnitGeometry0, GL_TEXTURE_2D, geometry_.geometry0().get());
    bind(kUnitGeometry1, GL_TEXTURE_2D, geometry_.geometry1().get());
    bind(kUnitUv, GL_TEXTURE_2D, geometry_.uv().get());
    bind(kUnitWeights, GL_TEXTURE_2D_ARRAY, weights != nullptr ? weights->get() : 0);
    for (int r = 0; r < textures_.layout().regions; ++r) {
        bind(kUnitMaps + r, GL_TEXTURE_2D_ARRAY, textures_.map(static_cast<std::size_t>(r)).get());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glViewport(0, 0, geometry_.width(), geometry_.height());
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    for (const Group& group : groups_) {
        std::array<GLenum, kMaxAttachments> buffers{};
        for (int k = 0; k < kMaxAttachments; ++k) {
            const bool used = k < group.count;
            glFramebufferTextureLayer(GL_FRAMEBUFFER, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + k),
                                      used ? target.get() : 0, 0, used ? group.first + k : 0);
            buffers[static_cast<std::size_t>(k)] =
                used ? static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + k) : GL_NONE;
        }
        glDrawBuffers(group.count, buffers.data());
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            throw GraphicsError("the material pass's RGBA32UI attachments are incomplete");
        }
        glUseProgram(group.program.get());
        glUniform1i(group.region, region);
        glUniform3fv(group.viewer, 1, viewer_.data());
        tiles_.draw();  // pixels off the object are never read
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("the material pass");
}

}  // namespace vpe::renderer::gles
