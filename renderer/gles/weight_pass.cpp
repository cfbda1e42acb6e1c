// SPDX-License-Identifier: MIT
// WeightPass: the presets' α per projector pixel (see the header).
#include "weight_pass.h"

#include <array>
#include <string>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"

#include "texture_formats.h"

namespace vpe::renderer::gles {

namespace {

constexpr int kUnitUv = 0, kUnitWeights = 1;
constexpr int kMaxAttachments = 4;  // GL_MAX_DRAW_BUFFERS in GLES 3.1 is at least 4

}  // namespace

WeightPass::WeightPass(const ThetaTextures& textures, const GeometryBuffer& geometry,
                       const TileCover& tiles) {
    const ShaderLayout& layout = textures.layout();
    const int layers = layout.alphaLayers();
    if (layers > kMaxAttachments) {
        throw GraphicsError(std::to_string(layout.regions) +
                            " regions need more than four colour attachments for their α");
    }
    const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
    unsigned fragment = 0;
    try {
        fragment =
            compileShader(GL_FRAGMENT_SHADER, "weights.frag", weightPassShaderSource(layout));
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    GlObject program = GlObject::program(linkProgram("weights", vertex, fragment));
    glUseProgram(program.get());
    glUniform1i(glGetUniformLocation(program.get(), "uUv"), kUnitUv);
    glUniform1i(glGetUniformLocation(program.get(), "uWeights"), kUnitWeights);
    glUniform1i(glGetUniformLocation(program.get(), "uTopRowAtOrigin"), 1);
    glUniform2f(glGetUniformLocation(program.get(), "uSize"), static_cast<float>(geometry.width()),
                static_cast<float>(geometry.height()));
    GlObject framebuffer = GlObject::framebuffer();
    const GLenum format = alphaFormat(layout.regions);
    const GLenum channels = format == GL_RG16F ? GL_RG : GL_RGBA;
    for (std::size_t preset = 0; preset < textures.presetCount(); ++preset) {
        GlObject target =
            makeArrayTexture(format, geometry.width(), geometry.height(), layers, channels,
                             GL_HALF_FLOAT, nullptr, TextureFilter::kNearest);
        glActiveTexture(GL_TEXTURE0 + kUnitUv);
        glBindTexture(GL_TEXTURE_2D, geometry.uv().get());
        glActiveTexture(GL_TEXTURE0 + kUnitWeights);
        glBindTexture(GL_TEXTURE_2D_ARRAY, textures.weights(preset).get());
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.get());
        std::array<GLenum, kMaxAttachments> buffers{};
        for (int k = 0; k < layers; ++k) {
            glFramebufferTextureLayer(GL_FRAMEBUFFER, static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + k),
                                      target.get(), 0, k);
            buffers[static_cast<std::size_t>(k)] = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + k);
        }
        glDrawBuffers(layers, buffers.data());
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            throw GraphicsError("the weight pass's " + internalFormatName(format) +
                                " attachments are incomplete");
        }
        glViewport(0, 0, geometry.width(), geometry.height());
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        tiles.draw();  // pixels off the object are never read
        alpha_.push_back(std::move(target));
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("the weight pass");
}

}  // namespace vpe::renderer::gles
