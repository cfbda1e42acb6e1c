// SPDX-License-Identifier: MIT
// MaterialPass: compose projector-space coded materials (see the header).
#include "material_pass.h"

#include <algorithm>
#include <string>
#include <vector>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"

#include "material_codes.h"
#include "texture_formats.h"

namespace vpe::renderer::gles {

namespace {

// Texture units of the sampling pass: geometry 0–1, uv 2, weights 3, the regions' maps from 4.
constexpr int kUnitGeometry0 = 0, kUnitGeometry1 = 1, kUnitUv = 2, kUnitWeights = 3, kUnitMaps = 4;
// Of the blending pass: the α 0, region r's codes 1 + 2r and kd codes 2 + 2r.
constexpr int kUnitAlpha = 0, kUnitRegions = 1;
constexpr int kMaxAttachments = 4;  // GL_MAX_DRAW_BUFFERS in GLES 3.1 is at least 4

void bind(int unit, GLenum kind, unsigned texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
    glBindTexture(kind, texture);
}

}  // namespace

MaterialPass::MaterialPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
                           const TileCover& tiles, const ViewerEyes& eyes)
    : textures_(textures), geometry_(geometry), tiles_(tiles), eyes_(eyes) {
    const ShaderLayout& layout = textures.layout();
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    if (kUnitMaps + layout.regions > units || kUnitRegions + 2 * layout.regions > units) {
        throw GraphicsError(std::to_string(layout.regions) +
                            " regions need more texture units than the " + std::to_string(units) +
                            " the GPU has");
    }
    sample_ = groups(false);
    blend_ = groups(true);
    framebuffer_ = GlObject::framebuffer();
    checkGlError("building the material pass");
}

std::vector<MaterialPass::Group> MaterialPass::groups(bool compose) {
    const ShaderLayout& layout = textures_.layout();
    const MaterialCoding& coding = textures_.coding();
    std::vector<Group> result;
    // The kd codes with the first code layers, the rest four layers a draw.
    for (int first = 0; first < layout.materialLayers();) {
        Group group;
        group.first = first;
        group.diffuse = first == 0;
        group.count =
            std::min(kMaxAttachments - (group.diffuse ? 1 : 0), layout.materialLayers() - first);
        first += group.count;
        const std::string name =
            std::string(compose ? "blend" : "material") + std::to_string(group.first) + ".frag";
        const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
        unsigned fragment = 0;
        try {
            fragment = compileShader(
                GL_FRAGMENT_SHADER, name,
                compose
                    ? composePassShaderSource(layout, group.first, group.count, group.diffuse)
                    : materialPassShaderSource(layout, group.first, group.count, group.diffuse));
        } catch (...) {
            glDeleteShader(vertex);
            throw;
        }
        group.program = GlObject::program(linkProgram(name, vertex, fragment));
        const GLuint program = group.program.get();
        const auto location = [program](const std::string& uniform) {
            return glGetUniformLocation(program, uniform.c_str());
        };
        glUseProgram(program);
        // The material textures' rows are the projector's, top row first.
        glUniform1i(location("uTopRowAtOrigin"), 1);
        glUniform2f(location("uSize"), static_cast<float>(geometry_.width()),
                    static_cast<float>(geometry_.height()));
        if (compose) {
            glUniform1i(location("uAlpha"), kUnitAlpha);
            for (int r = 0; r < layout.regions; ++r) {
                glUniform1i(location("uRegion" + std::to_string(r)), kUnitRegions + 2 * r);
                glUniform1i(location("uRegion" + std::to_string(r) + "Diffuse"),
                            kUnitRegions + 2 * r + 1);
            }
            glUniform1f(location("uDiffuseLow"), coding.diffuseLow() / coding.diffuseSpan());
        } else {
            glUniform1i(location("uGeometry0"), kUnitGeometry0);
            glUniform1i(location("uGeometry1"), kUnitGeometry1);
            glUniform1i(location("uUv"), kUnitUv);
            glUniform1i(location("uWeights"), kUnitWeights);
            for (int r = 0; r < layout.regions; ++r) {
                glUniform1i(location("uThetaMap" + std::to_string(r)), kUnitMaps + r);
            }
            glUniform1f(location("uDiffuseLow"), coding.diffuseLow());
            glUniform1f(location("uDiffuseScale"),
                        static_cast<float>(kDiffuseCodeMax) / coding.diffuseSpan());
            std::vector<float> inverseSteps;
            for (int k = 0; k < layout.basisSize; ++k) {
                const float step = coding.basisStep(k);
                inverseSteps.push_back(step > 0.0f ? 1.0f / step : 0.0f);
            }
            glUniform1fv(location("uInverseBasisStep"), layout.basisSize, inverseSteps.data());
            group.region = location("uRegion");
            eyes_.setUniforms(program);
        }
        result.push_back(std::move(group));
    }
    return result;
}

CodedMaterial MaterialPass::makeTarget() const {
    CodedMaterial target;
    target.codes = makeArrayTexture(kMaterialFormat, geometry_.width(), geometry_.height(),
                                    textures_.layout().materialLayers(), GL_RGBA_INTEGER, GL_INT,
                                    nullptr, TextureFilter::kNearest);
    target.diffuse =
        makeTexture2D(kDiffuseFormat, geometry_.width(), geometry_.height(), GL_RGBA,
                      GL_UNSIGNED_INT_2_10_10_10_REV, nullptr, TextureFilter::kNearest);
    return target;
}

void MaterialPass::composeRegion(const CodedMaterial& target, int region) {
    sample(target, region, nullptr);
}

void MaterialPass::composePreset(const CodedMaterial& target, std::size_t preset) {
    sample(target, -1, &textures_.weights(preset));
}

void MaterialPass::sample(const CodedMaterial& target, int region, const GlObject* weights) {
    bind(kUnitGeometry0, GL_TEXTURE_2D, geometry_.geometry0().get());
    bind(kUnitGeometry1, GL_TEXTURE_2D, geometry_.geometry1().get());
    bind(kUnitUv, GL_TEXTURE_2D, geometry_.uv().get());
    bind(kUnitWeights, GL_TEXTURE_2D_ARRAY, weights != nullptr ? weights->get() : 0);
    for (int r = 0; r < textures_.layout().regions; ++r) {
        bind(kUnitMaps + r, GL_TEXTURE_2D_ARRAY, textures_.map(static_cast<std::size_t>(r)).get());
    }
    for (const Group& group : sample_) {
        glUseProgram(group.program.get());
        glUniform1i(group.region, region);
        draw(target, group);
    }
}

void MaterialPass::blendRegions(const CodedMaterial& target,
                                const std::vector<CodedMaterial>& regions, const GlObject& alpha) {
    bind(kUnitAlpha, GL_TEXTURE_2D_ARRAY, alpha.get());
    for (std::size_t r = 0; r < regions.size(); ++r) {
        bind(kUnitRegions + 2 * static_cast<int>(r), GL_TEXTURE_2D_ARRAY, regions[r].codes.get());
        bind(kUnitRegions + 2 * static_cast<int>(r) + 1, GL_TEXTURE_2D, regions[r].diffuse.get());
    }
    for (const Group& group : blend_) {
        glUseProgram(group.program.get());
        draw(target, group);
    }
}

void MaterialPass::draw(const CodedMaterial& target, const Group& group) {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glViewport(0, 0, geometry_.width(), geometry_.height());
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    std::array<GLenum, kMaxAttachments> buffers{};
    for (int k = 0; k < kMaxAttachments; ++k) {
        const auto attachment = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + k);
        if (k < group.count) {
            glFramebufferTextureLayer(GL_FRAMEBUFFER, attachment, target.codes.get(), 0,
                                      group.first + k);
        } else if (k == group.count && group.diffuse) {
            glFramebufferTextureLayer(GL_FRAMEBUFFER, attachment, 0, 0, 0);
            glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, target.diffuse.get(),
                                   0);
        } else {
            glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, 0, 0);
        }
        const bool used = k < group.count + (group.diffuse ? 1 : 0);
        buffers[static_cast<std::size_t>(k)] = used ? attachment : GL_NONE;
    }
    glDrawBuffers(kMaxAttachments, buffers.data());
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        throw GraphicsError("the material pass's RGBA32I and RGB10_A2 attachments are incomplete");
    }
    tiles_.draw();  // pixels off the object are never read
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("the material pass");
}

}  // namespace vpe::renderer::gles
