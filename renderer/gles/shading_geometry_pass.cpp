// SPDX-License-Identifier: MIT
// ShadingGeometryPass: pack the frame's per-pixel shading geometry (see the header).
#include "shading_geometry_pass.h"

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"

#include "shading_glsl.h"
#include "texture_formats.h"

namespace vpe::renderer::gles {

namespace {

constexpr int kUnitGeometry0 = 0, kUnitGeometry1 = 1;

void bind(int unit, unsigned texture) {
    glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, texture);
}

}  // namespace

std::string shadingGeometryShaderSource() {
    return R"GLSL(#version 310 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp usampler2D;
)GLSL" + shadingStepsGlsl() +
           R"GLSL(
uniform highp sampler2D uGeometry0;   // X, 1/S
uniform highp usampler2D uGeometry1;  // n (float bits), g (octahedral)
uniform vec3 uViewer;
uniform vec3 uZone[VPE_MAX_VIEWING_ZONE];  // the viewing zone's eyes (ViewerEyes)
uniform int uZoneCount;
uniform vec3 uCubeLow;   // the covered positions' cube: its low corner
uniform float uCubeScale;  // 1023 / its side
layout(location = 0) out uvec4 outShading;
layout(location = 1) out vec4 outPosition;  // X in the cube, 10 bits an axis; 1 on the object

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);  // rows = projector rows, as the geometry buffer
    vec4 geometry0 = texelFetch(uGeometry0, pixel, 0);
    if (geometry0.w < 0.0) {  // sees nothing
        outShading = uvec4(0u);
        outPosition = vec4(0.0);
        return;
    }
    vec3 position = geometry0.xyz;
    // The nearest of the 1024 steps, so that no GPU's own rounding as it writes the texel moves it.
    outPosition =
        vec4(clamp(floor((position - uCubeLow) * uCubeScale + 0.5), 0.0, 1023.0) / 1023.0, 1.0);
    uvec4 geometry1 = texelFetch(uGeometry1, pixel, 0);
    vec3 normal = uintBitsToFloat(geometry1.xyz);
    vec3 geometric = vpeOctahedralNormal(geometry1.w);
    vec3 eye = vpeZoneViewer(position, geometric, uViewer, uZone, uZoneCount);
    vec3 mirrored = vpeMirroredViewer(normal, normalize(eye - position));
    outShading = uvec4(packHalf2x16(normal.xy), packHalf2x16(vec2(normal.z, mirrored.x)),
                       packHalf2x16(mirrored.yz), packHalf2x16(geometric.xy));
}
)GLSL";
}

ShadingGeometryPass::ShadingGeometryPass(const GeometryBuffer& geometry, const TileCover& tiles,
                                         const ViewerEyes& eyes)
    : geometry_(geometry), tiles_(tiles), eyes_(eyes) {
    shading_ = makeTexture2D(kShadingFormat, geometry.width(), geometry.height(), GL_RGBA_INTEGER,
                             GL_UNSIGNED_INT, nullptr);
    position_ = makeTexture2D(kPositionFormat, geometry.width(), geometry.height(), GL_RGBA,
                              GL_UNSIGNED_INT_2_10_10_10_REV, nullptr);
    const unsigned vertex = compileShader(GL_VERTEX_SHADER, "tiles.vert", tileVertexSource());
    unsigned fragment = 0;
    try {
        fragment = compileShader(GL_FRAGMENT_SHADER, "shading.frag", shadingGeometryShaderSource());
    } catch (...) {
        glDeleteShader(vertex);
        throw;
    }
    program_ = GlObject::program(linkProgram("shading", vertex, fragment));
    const GLuint program = program_.get();
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "uGeometry0"), kUnitGeometry0);
    glUniform1i(glGetUniformLocation(program, "uGeometry1"), kUnitGeometry1);
    glUniform1i(glGetUniformLocation(program, "uTopRowAtOrigin"), 1);
    glUniform2f(glGetUniformLocation(program, "uSize"), static_cast<float>(geometry.width()),
                static_cast<float>(geometry.height()));
    eyes_.setUniforms(program);
    const GeometryBuffer::Cube& cube = geometry.cube();
    glUniform3f(glGetUniformLocation(program, "uCubeLow"), static_cast<float>(cube.low[0]),
                static_cast<float>(cube.low[1]), static_cast<float>(cube.low[2]));
    glUniform1f(glGetUniformLocation(program, "uCubeScale"),
                static_cast<float>(1023.0 / cube.side));
    framebuffer_ = GlObject::framebuffer();
    checkGlError("building the shading geometry pass");
}

void ShadingGeometryPass::run() {
    bind(kUnitGeometry0, geometry_.geometry0().get());
    bind(kUnitGeometry1, geometry_.geometry1().get());
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, shading_.get(), 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, position_.get(), 0);
    const std::array<GLenum, 2> buffers{GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers.data());
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        throw GraphicsError(
            "the shading geometry pass's RGBA32UI and RGB10_A2 attachments are "
            "incomplete");
    }
    // Pixels of tiles the pass does not draw: off the object (alpha 0) for a full-screen frame.
    const std::array<GLfloat, 4> none{0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 1, none.data());
    glViewport(0, 0, geometry_.width(), geometry_.height());
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glUseProgram(program_.get());
    tiles_.draw();  // pixels off the object are never read
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("the shading geometry pass");
}

}  // namespace vpe::renderer::gles
