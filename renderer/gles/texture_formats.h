// SPDX-License-Identifier: MIT
// The sized internal formats of the textures a frame reads and of the target it writes, one
// constant each, used where the texture is allocated and named in the generated shaders'
// declarations (`uniform highp sampler2D uGeometry0;  // RGBA32F: ...`), which is how
// vpe_shader_cost counts a pixel's bytes (docs/shader-cost.md).
#pragma once

#include <string>

#include <GLES3/gl31.h>

namespace vpe::renderer::gles {

inline constexpr GLenum kGeometry0Format = GL_RGBA32F;   // X, 1/S
inline constexpr GLenum kGeometry1Format = GL_RGBA32UI;  // n (float bits), g (octahedral)
inline constexpr GLenum kShadingFormat = GL_RGBA32UI;    // n, m, g.xy as half floats
inline constexpr GLenum kPositionFormat = GL_RGB10_A2;   // X in the object's cube, covered
inline constexpr GLenum kUvFormat = GL_RG32F;            // uv
inline constexpr GLenum kMaterialFormat = GL_RGBA32I;    // u codes, 1/S and g.z
inline constexpr GLenum kDiffuseFormat = GL_RGB10_A2;    // kd codes (material_codes.h)
inline constexpr GLenum kThetaTableFormat = GL_RGBA16F;  // h_j(x)
inline constexpr GLenum kLevelTableFormat = GL_RGBA16F;  // the response inverse
inline constexpr GLenum kMeasuredFormat = GL_RGBA16F;    // F, D, the measured inverse
inline constexpr GLenum kFrameTargetFormat = GL_RGBA8;   // the drive levels
// Live weights: the regions' α per projector pixel (the weight pass), two regions or four.
inline constexpr GLenum alphaFormat(int regions) {
    return regions <= 2 ? GL_RG16F : GL_RGBA16F;
}

// "RGBA32F" for GL_RGBA32F: the formats above and the weights' (R8, R16F); throws
// std::invalid_argument for another.
std::string internalFormatName(GLenum internalFormat);

}  // namespace vpe::renderer::gles
