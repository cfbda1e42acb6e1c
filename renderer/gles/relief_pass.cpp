// SPDX-License-Identifier: MIT
// ReliefPass: upload the detail normals, fold them into geometry1 (see the header).
#include "relief_pass.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

namespace {

// Texture units of the pass.
constexpr int kUnitTraced = 0, kUnitTangents = 1, kUnitUv = 2, kUnitDetail = 3, kUnitWeights = 4;

void bind(int unit, GLenum kind, unsigned texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
    glBindTexture(kind, texture);
}

}  // namespace

bool ReliefPass::needed(const proto::BundleView& bundle) {
    return std::any_of(
        bundle.regions().begin(), bundle.regions().end(),
        [](const proto::RegionView& region) { return !region.coefficients.detailNormals.empty(); });
}

ReliefPass::ReliefPass(const proto::BundleView& bundle, GeometryBuffer& geometry,
                       const ThetaTextures& textures, const TileCover& tiles)
    : geometry_(geometry), textures_(textures), tiles_(tiles) {
    if (!geometry.relief()) {
        throw std::logic_error("ReliefPass: the geometry buffer has no relief textures");
    }
    const int w = bundle.textureWidth(), h = bundle.textureHeight();
    const auto texels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    const auto regions = bundle.regions().size();
    // Half floats straight from the mapping; flat (0, 0) for a region without a relief.
    std::vector<std::uint16_t> layers(regions * texels * 2, 0);
    for (std::size_t r = 0; r < regions; ++r) {
        const auto& detail = bundle.regions()[r].coefficients.detailNormals;
        std::copy(detail.begin(), detail.end(), layers.begin() + static_cast<long>(r * texels * 2));
    }
    // A relief that tiles around the object repeats in u, as its coefficients and weights do.
    detail_ =
        makeArrayTexture(GL_RG16F, w, h, static_cast<int>(regions), GL_RG, GL_HALF_FLOAT,
                         layers.data(), TextureFilter::kLinear,
                         bundle.textureWrapsU() ? TextureWrapS::kRepeat : TextureWrapS::kClamp);

    const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
    unsigned fragment = 0;
    try {
        fragment = compileShader(GL_FRAGMENT_SHADER, "relief.frag",
                                 reliefPassShaderSource(textures.layout()));
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    program_ = GlObject::program(linkProgram("relief", vertex, fragment));
    const GLuint program = program_.get();
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "uTracedGeometry1"), kUnitTraced);
    glUniform1i(glGetUniformLocation(program, "uTangents"), kUnitTangents);
    glUniform1i(glGetUniformLocation(program, "uUv"), kUnitUv);
    glUniform1i(glGetUniformLocation(program, "uDetail"), kUnitDetail);
    glUniform1i(glGetUniformLocation(program, "uWeights"), kUnitWeights);
    glUniform1i(glGetUniformLocation(program, "uTopRowAtOrigin"), 1);
    glUniform2f(glGetUniformLocation(program, "uSize"), static_cast<float>(geometry.width()),
                static_cast<float>(geometry.height()));
    regionUniform_ = glGetUniformLocation(program, "uRegion");
    framebuffer_ = GlObject::framebuffer();
    checkGlError(bundle.name() + ": building the relief pass");
}

void ReliefPass::composeRegion(int region) {
    run(region, nullptr);
}

void ReliefPass::composePreset(std::size_t preset) {
    run(-1, &textures_.weights(preset));
}

void ReliefPass::run(int region, const GlObject* weights) {
    bind(kUnitTraced, GL_TEXTURE_2D, geometry_.tracedGeometry1().get());
    bind(kUnitTangents, GL_TEXTURE_2D, geometry_.tangents().get());
    bind(kUnitUv, GL_TEXTURE_2D, geometry_.uv().get());
    bind(kUnitDetail, GL_TEXTURE_2D_ARRAY, detail_.get());
    bind(kUnitWeights, GL_TEXTURE_2D_ARRAY, weights != nullptr ? weights->get() : 0);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                           geometry_.geometry1().get(), 0);
    const GLenum buffer = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &buffer);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        throw GraphicsError("the relief pass's RGBA32UI attachment is incomplete");
    }
    glViewport(0, 0, geometry_.width(), geometry_.height());
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(program_.get());
    glUniform1i(regionUniform_, region);
    tiles_.draw();  // pixels off the object keep what was traced (nothing is read there)
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("the relief pass");
}

}  // namespace vpe::renderer::gles
