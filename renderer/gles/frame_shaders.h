// SPDX-License-Identifier: MIT
// The GLSL the GLES renderer compiles, generated per bundle: the material pass (run at load and
// when the preset changes) and the frame (run every frame). Straight-line code with the
// bundle's sizes and response baked in, so that no array is indexed dynamically and nothing but
// the textures is loaded (renderer/gles/README.md says why).
#pragma once

#include <string>

#include "vpe/proto/bundle_contents.h"
#include "vpe/renderer/gles/frame_variant.h"

namespace vpe::renderer::gles {

// Samples of the measured light's inverse response table (proto::InverseResponseTable).
inline constexpr int kInverseResponseSamples = 256;

// The sizes a shader is generated for.
struct ShaderLayout {
    int basisSize = 0;  // K: θs functions (proto::ThetaBasis::size)
    int regions = 0;
    int tableSamples = 0;  // samples of the θs table (proto::ThetaTable::samples)
    // The bundle carries the light measured on site (format 1.4): the frame compensates with
    // its maps (renderer::compensateMeasuredPixel) instead of the assumed albedo and ambient.
    bool measuredLight = false;
    int tableRows() const { return (basisSize + 3) / 4; }
    // A material is proto::thetaMaterialSize(K) values: kd (RGB), then u_j (RGB) per function.
    int materialValues() const { return 3 * (1 + basisSize); }
    // In texture space, RGBA16F layers of 4 values.
    int mapLayers() const { return (materialValues() + 3) / 4; }
    // In projector space, the codes of material_codes.h: RGBA32I layers (K = 4: one, the three
    // channels' u and a word of 1/S and the geometric normal's z) and kd in an RGB10_A2 texel.
    int materialLayers() const;
    // The frame evaluates f in units of the coding's frameUnit(), kd's span: kd = code/1023 +
    // diffuseOffset in those units (MaterialCoding's low end over its span; 0 unless some kd < 0).
    float diffuseOffset = 0.0f;
    // The bundle's textures repeat in u (the weight pass filters them as GL_REPEAT does).
    bool wrapU = false;
    // With live weights, the regions' α per projector pixel (the weight pass): four a texel.
    int alphaLayers() const { return (regions + 3) / 4; }
};

// The frame's fragment shader (full-screen triangle): fetch the pixel's geometry and material,
// evaluate the model for the light through the θs table, apply the horizon, compensate for the
// projector, output RGBA8 drive levels. `settings` gives the response and whether room light
// is subtracted; `inverseSquare`, whether the light falls off with distance (a program each,
// so that neither pays for the other's arithmetic).
std::string frameShaderSource(const ShaderLayout& layout, FrameVariant variant,
                              const proto::RenderSettings& settings, bool inverseSquare);

// The material pass's fragment shader writing code layers [first, first + count) (one colour
// attachment each) and, with `diffuse`, the kd codes (one more): per pixel, the texture-space θs
// maps at the pixel's uv, one region alone or all blended by a preset's weights, scaled by the
// viewer's horizon factor (fixed per pixel), coded as material_codes.h says with the coding in
// its uniforms (uDiffuseLow, uDiffuseScale = 1023/span, uInverseBasisStep[k]).
std::string materialPassShaderSource(const ShaderLayout& layout, int first, int count,
                                     bool diffuse);

// The compose pass's (live weights): per pixel, the regions' coded materials blended by a
// preset's α (the weight pass's) and coded again — in code units, since every region shares the
// coding — writing code layers [first, first + count) and, with `diffuse`, the kd codes.
std::string composePassShaderSource(const ShaderLayout& layout, int first, int count, bool diffuse);

// The relief pass's fragment shader: per pixel, the regions' detail normals at the pixel's uv —
// one region alone, or all blended by a preset's weights (a region without a relief map is flat
// there) — folded into the traced shading normal through the pixel's tangent frame
// (renderer::shadingNormal), written with the geometric normal as geometry1 is.
std::string reliefPassShaderSource(const ShaderLayout& layout);

// The weight pass's fragment shader (live weights): per projector pixel, each region's α of a
// preset at the pixel's uv, filtered bilinearly in the shader from the weights' texels
// (vpeBilinearWeight, the CPU reference's footprint: the result does not depend on the GPU's
// filter precision), written four regions a texel (RGBA16F, RG16F for two regions).
std::string weightPassShaderSource(const ShaderLayout& layout);

// A shader reading exactly the textures `frameShaderSource` reads per pixel, summing them and
// doing nothing else: the texture-fetch floor a frame is compared with.
std::string passThroughShaderSource(const ShaderLayout& layout, FrameVariant variant);

// The vertex shader of a full-screen triangle.
std::string fullScreenVertexSource();

}  // namespace vpe::renderer::gles
