// SPDX-License-Identifier: MIT
// GLSL generation for the material pass and the frame (see the header).
#include "vpe/renderer/gles/frame_shaders.h"

#include <vector>

#include "vpe/renderer/gles/geometry_buffer.h"
#include "vpe/renderer/gles/shading_glsl.h"
#include "vpe/renderer/gles/texture_formats.h"

namespace vpe::renderer::gles {

namespace {

const char* const kPrecision = R"GLSL(#version 310 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp usampler2D;
precision highp sampler2DArray;
precision highp usampler2DArray;
)GLSL";

std::string str(int value) {
    return std::to_string(value);
}

std::string component(int i) {
    return std::string(1, "xyzw"[i]);
}

// "  // RGBA32F: what" — the declaration comment naming the texture's format, which
// vpe_shader_cost reads to count the bytes a pixel fetches (texture_formats.h).
std::string declared(unsigned format, const std::string& what, bool cached = false) {
    return "  // " + internalFormatName(format) + (cached ? " cached: " : ": ") + what + "\n";
}

// The load passes' view of the geometry buffer (geometry_buffer.h).
std::string geometryUniforms() {
    return "\nuniform highp sampler2D uGeometry0;" + declared(kGeometry0Format, "X, 1/S") +
           "uniform highp usampler2D uGeometry1;" +
           declared(kGeometry1Format, "n (float bits), g (octahedral)") +
           "uniform highp sampler2D uUv;" + declared(kUvFormat, "uv, rows from the top");
}

// The frame's: X about the centre and 1/S, the packed shading geometry
// (shading_geometry_pass.h), uv.
std::string frameGeometryUniforms() {
    return "\nuniform highp sampler2D uPosition;" +
           declared(kPositionFormat, "X − centre, 1/S as half floats") +
           "uniform highp usampler2D uShading;" +
           declared(kShadingFormat, "n, m = 2(n·v)n − v, g.xy as half floats") +
           "uniform highp sampler2D uUv;" + declared(kUvFormat, "uv, rows from the top");
}

// Statements fetching material `sampler` at `pixel` and naming its values: half floats, two a
// word, eight a layer, in thetaMaterialSize order.
std::string unpackMaterial(const ShaderLayout& layout, const std::string& sampler,
                           const std::string& prefix) {
    std::string s;
    for (int l = 0; l < layout.materialLayers(); ++l) {
        s += "    uvec4 " + prefix + "w" + str(l) + " = texelFetch(" + sampler + ", ivec3(pixel, " +
             str(l) + "), 0);\n";
    }
    for (int word = 0; 2 * word < layout.materialValues() + 1; ++word) {  // and the spare
        s += "    vec2 " + prefix + "h" + str(word) + " = unpackHalf2x16(" + prefix + "w" +
             str(word / 4) + "." + component(word % 4) + ");\n";
    }
    return s;
}

// The expression of material value q (after unpackMaterial).
std::string unpacked(const std::string& prefix, int q) {
    return prefix + "h" + str(q / 2) + "." + (q % 2 == 0 ? "x" : "y");
}

}  // namespace

const char* frameVariantName(FrameVariant variant) {
    switch (variant) {
        case FrameVariant::kStatic:
            return "static";
        case FrameVariant::kFade:
            return "fade";
        case FrameVariant::kLive:
            return "live";
        case FrameVariant::kLiveFade:
            return "live-fade";
    }
    return "?";
}

std::string fullScreenVertexSource() {
    return R"GLSL(#version 310 es
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";
}

std::string frameShaderSource(const ShaderLayout& layout, FrameVariant variant,
                              const proto::RenderSettings& settings) {
    const bool live = variant == FrameVariant::kLive || variant == FrameVariant::kLiveFade;
    const bool fade = variant == FrameVariant::kFade || variant == FrameVariant::kLiveFade;
    const bool ambient = settings.ambientIrradiance[0] != 0 || settings.ambientIrradiance[1] != 0 ||
                         settings.ambientIrradiance[2] != 0;
    const int values = layout.materialValues();
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    if (!layout.measuredLight) {
        s += projectorLevelTableGlsl(kProjectorLevelSamples);
    } else {
        s += measuredLightGlsl(kInverseResponseSamples);
        s += "uniform highp sampler2D uMeasuredIrradiance;" +
             declared(kMeasuredFormat, "F per projector pixel") +
             "uniform highp sampler2D uMeasuredFloor;" +
             declared(kMeasuredFormat, "D per projector pixel") +
             "uniform mat3 uMixingInverse;  // X⁻¹\n";
    }
    s += frameGeometryUniforms();
    s += "\nuniform highp sampler2D uThetaTable;" +
         declared(kThetaTableFormat, "h_j(x), row r holds j = 4r … 4r+3 (linear)", true);
    s +=
        R"GLSL(uniform vec2 uRow;  // (0, 1) on a target whose top row is at its origin, else (H − ½, −1)
uniform vec3 uLightPosition;  // less the centre the positions are stored about
// gain · intensity (· π/ρ when assumed) (· d_ref² with 1/d²); without measured light also
// · (N − 1)/N, the level table's coordinate scale (vpeProjectorLevelTable), as uAmbient.
uniform vec3 uRadianceScale;
uniform float uFalloff;       // 1: inverse-square falloff, 0: none
uniform vec3 uAmbient;        // room light on the plaster (E_ambient)
uniform float uFade;          // fading: 0 the old material or weights, 1 the new
layout(location = 0) out vec4 outLevel;)GLSL";
    s += declared(kFrameTargetFormat, "the drive levels");
    if (live) {
        for (int r = 0; r < layout.regions; ++r) {
            s += "uniform highp usampler2DArray uRegionMaterial" + str(r) + ";" +
                 declared(kMaterialFormat, "region " + str(r) + "'s material");
        }
        s += "uniform highp sampler2DArray uAlpha;" +
             declared(alphaFormat(layout.regions), "the regions' α per pixel (weight pass)");
        s += "uniform highp sampler2DArray uAlphaFrom;" +
             declared(alphaFormat(layout.regions), "fading: the old preset's");
    } else {
        s += "uniform highp usampler2DArray uMaterial;" +
             declared(kMaterialFormat, "the composed material");
        s += "uniform highp usampler2DArray uMaterialFrom;" +
             declared(kMaterialFormat, "fading: the old one");
    }
    s += R"GLSL(
void main() {
    // The projector's row: y, or (height − ½) − y on a target whose top row is at the top.
    ivec2 pixel = ivec2(gl_FragCoord.x, uRow.x + uRow.y * gl_FragCoord.y);
    vec4 position = texelFetch(uPosition, pixel, 0);
    float inverseScale = position.w;
    if (inverseScale < 0.0) {  // sees nothing
        outLevel = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    uvec4 shading = texelFetch(uShading, pixel, 0);
    vec2 s0 = unpackHalf2x16(shading.x);
    vec2 s1 = unpackHalf2x16(shading.y);
    vec2 s2 = unpackHalf2x16(shading.z);
    vec2 s3 = unpackHalf2x16(shading.w);
    vec3 normal = vec3(s0, s1.x);
    vec3 mirrored = vec3(s1.y, s2);  // 2(n·v)n − v: the viewer is fixed per pixel
    vec3 toLight = uLightPosition - position.xyz;  // both about the centre
    float inverseLightDistance = inversesqrt(dot(toLight, toLight));
    vec3 l = toLight * inverseLightDistance;
    vec2 angles = vpeMirroredReflectionAngles(normal, l, mirrored);
)GLSL";
    // The θs table, one fetch per four functions; sample s of N at texture coordinate
    // (s + ½)/N, so parameter x ∈ [0, 1] maps to x·(N − 1)/N + ½/N.
    const int rows = layout.tableRows();
    const auto samples = static_cast<float>(layout.tableSamples);
    s += "    float tableX = vpeThetaTableCoordinate(angles.y, " +
         glslFloat((samples - 1.0f) / samples) + ", " + glslFloat(0.5f / samples) + ");\n";
    for (int r = 0; r < rows; ++r) {
        s += "    vec4 h" + str(r) + " = texture(uThetaTable, vec2(tableX, " +
             glslFloat((static_cast<float>(r) + 0.5f) / static_cast<float>(rows)) + "));\n";
    }
    // The material: value q of the (blended) codes; the spare half after them is the geometric
    // normal's z (the same in every material: region 0's, or the one faded to).
    std::vector<std::string> m(static_cast<std::size_t>(values));
    std::string geometricZ;
    if (live) {
        // The regions' α at the pixel, filtered once per preset by the weight pass.
        for (int k = 0; k < layout.alphaLayers(); ++k) {
            const std::string to = "texelFetch(uAlpha, ivec3(pixel, " + str(k) + "), 0)";
            s += "    vec4 alphas" + str(k) + " = " +
                 (fade ? "mix(texelFetch(uAlphaFrom, ivec3(pixel, " + str(k) + "), 0), " + to +
                             ", uFade)"
                       : to) +
                 ";\n";
        }
        for (int r = 0; r < layout.regions; ++r) {
            s += "    float alpha" + str(r) + " = alphas" + str(r / 4) + "." + component(r % 4) +
                 ";\n";
            s += unpackMaterial(layout, "uRegionMaterial" + str(r), "r" + str(r) + "_");
        }
        geometricZ = unpacked("r0_", values);
    } else {
        s += unpackMaterial(layout, "uMaterial", "to_");
        if (fade) {
            s += unpackMaterial(layout, "uMaterialFrom", "from_");
        }
        for (int q = 0; q < values; ++q) {
            m[static_cast<std::size_t>(q)] =
                fade ? "mix(" + unpacked("from_", q) + ", " + unpacked("to_", q) + ", uFade)"
                     : unpacked("to_", q);
        }
        geometricZ = unpacked("to_", values);
    }
    if (fade && !live) {  // mix once into plain floats, then evaluate
        for (int q = 0; q < values; ++q) {
            s += "    float m" + str(q) + " = " + m[static_cast<std::size_t>(q)] + ";\n";
            m[static_cast<std::size_t>(q)] = "m" + str(q);
        }
    }
    s += "    vec3 geometric = vec3(s3, " + geometricZ + ");\n";
    s +=
        R"GLSL(    // The light's half of the horizon; the viewer's half is in the material (fixed per pixel).
    float horizon = vpeHorizonFactor(min(angles.x, dot(geometric, l)));
)GLSL";
    const auto rgb = [](const std::vector<std::string>& values3, int term) {
        return "vec3(" + values3[static_cast<std::size_t>(3 * term)] + ", " +
               values3[static_cast<std::size_t>(3 * term + 1)] + ", " +
               values3[static_cast<std::size_t>(3 * term + 2)] + ")";
    };
    // f = kd·max(cos θd, 0) + Σ_j u_j h_j(θs) (renderer::evaluateThetaMaterial); the max is
    // left out: where cos θd ≤ 0 the horizon factor, which multiplies f, is 0.
    if (!live) {
        s += "    vec3 f = " + rgb(m, 0) + " * angles.x";
        for (int j = 0; j < layout.basisSize; ++j) {
            s += "\n        + " + rgb(m, 1 + j) + " * h" + str(j / 4) + "." + component(j % 4);
        }
    } else {
        // Σ_r α_r f_r with the weights folded into the table values and the cosine (1 + K/4
        // products a region) rather than into the 3(1 + K) material values.
        for (int r = 0; r < layout.regions; ++r) {
            s += "    float cosine" + str(r) + " = alpha" + str(r) + " * angles.x;\n";
            for (int row = 0; row < rows; ++row) {
                s += "    vec4 h" + str(row) + "_" + str(r) + " = alpha" + str(r) + " * h" +
                     str(row) + ";\n";
            }
        }
        s += "    vec3 f = ";
        for (int r = 0; r < layout.regions; ++r) {
            std::vector<std::string> own(static_cast<std::size_t>(values));
            for (int q = 0; q < values; ++q) {
                own[static_cast<std::size_t>(q)] = unpacked("r" + str(r) + "_", q);
            }
            s += (r == 0 ? "" : "\n        + ") + rgb(own, 0) + " * cosine" + str(r);
            for (int j = 0; j < layout.basisSize; ++j) {
                s += "\n        + " + rgb(own, 1 + j) + " * h" + str(j / 4) + "_" + str(r) + "." +
                     component(j % 4);
            }
        }
    }
    s += ";\n";
    if (layout.measuredLight) {
        s += R"GLSL(
    // L = max(gain · H · E · f, 0) (renderer's targetRadiance), then compensateMeasuredPixel
    // with the pixel's measured F and D.
    float irradiance = horizon * mix(1.0, inverseLightDistance * inverseLightDistance, uFalloff);
    vec3 target = max(uRadianceScale * (irradiance * f), 0.0);
    vec3 relative = vpeMeasuredOutputs(target, texelFetch(uMeasuredIrradiance, pixel, 0).rgb,
                                       texelFetch(uMeasuredFloor, pixel, 0).rgb, uMixingInverse);
    outLevel = vec4(vpeMeasuredLevel(relative), 1.0);
}
)GLSL";
        return s;
    }
    s += R"GLSL(
    // π/ρ·L, L = max(gain · H · E · f, 0) (renderer's targetRadiance), then compensatePixel:
    // r = (π·L/ρ − E_ambient) / S (S = 0: 1/S is kNoProjectorLight, clipping either way), the
    // uniforms scaled by (N − 1)/N: the level table's coordinate less its offset.
    float irradiance = horizon * mix(1.0, inverseLightDistance * inverseLightDistance, uFalloff);
    vec3 wanted = max(uRadianceScale * (irradiance * f), 0.0))GLSL";
    s += ambient ? " - uAmbient;\n" : ";\n";
    s += R"GLSL(    outLevel = vec4(vpeProjectorLevelTable(wanted * inverseScale), 1.0);
}
)GLSL";
    return s;
}

std::string materialPassShaderSource(const ShaderLayout& layout, int first, int count) {
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += bilinearWeightGlsl();
    s += geometryUniforms();
    for (int r = 0; r < layout.regions; ++r) {
        s += "uniform highp sampler2DArray uThetaMap" + str(r) +
             ";  // RGBA16F, texture space, 4 values a layer\n";
    }
    s += R"GLSL(uniform highp sampler2DArray uWeights;  // α, one layer per region
uniform int uRegion;  // ≥ 0: that region alone; −1: all, weighted by uWeights
uniform vec3 uViewer;
)GLSL";
    for (int k = 0; k < count; ++k) {
        s += "layout(location = " + str(k) + ") out uvec4 outLayer" + str(k) + ";\n";
    }
    s += R"GLSL(
void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);  // rows of the material textures = projector rows
    vec4 geometry0 = texelFetch(uGeometry0, pixel, 0);
    float viewerHorizon = 0.0;
    vec2 uv = vec2(0.0);
    vec3 geometric = vec3(0.0);
    if (geometry0.w >= 0.0) {  // sees the object
        uvec4 geometry1 = texelFetch(uGeometry1, pixel, 0);
        vec3 v = normalize(uViewer - geometry0.xyz);
        geometric = vpeOctahedralNormal(geometry1.w);
        viewerHorizon = vpeHorizonFactor(min(dot(uintBitsToFloat(geometry1.xyz), v),
                                             dot(geometric, v)));
        uv = texelFetch(uUv, pixel, 0).xy;
    }
)GLSL";
    // The preset's 8-bit weights filtered here rather than by the sampler: GPUs (and llvmpipe
    // on x86 and arm64) filter 8-bit texels at different precisions, up to a level apart on
    // the stripes' edges; in float they agree with renderer::bilinearFootprint.
    const std::string wrap = layout.wrapU ? "true" : "false";
    for (int r = 0; r < layout.regions; ++r) {
        s += "    float alpha" + str(r) +
             " = viewerHorizon * (uRegion < 0 ? vpeBilinearWeight(uWeights, uv, " + str(r) + ", " +
             wrap + ") : (uRegion == " + str(r) + " ? 1.0 : 0.0));\n";
    }
    // Value i of the blended θs maps, packed two a word as half floats.
    for (int l = 0; l < layout.mapLayers(); ++l) {
        std::string sum;
        for (int r = 0; r < layout.regions; ++r) {
            sum += (r == 0 ? "" : " + ") + std::string("alpha") + str(r) + " * texture(uThetaMap" +
                   str(r) + ", vec3(uv, " + str(l) + ".0))";
        }
        s += "    vec4 value" + str(l) + " = " + sum + ";\n";
    }
    // Value `index` of the blended maps, or after them the spare: the geometric normal's z
    // (the frame's shading geometry has no room for it), then zeros.
    const int values = layout.materialValues();
    const auto value = [&](int index) {
        if (index < values) {
            return "value" + str(index / 4) + "." + component(index % 4);
        }
        return std::string(index == values ? "geometric.z" : "0.0");
    };
    const auto word = [&](int w) {
        const int index = 2 * w;
        if (index > values) {
            return std::string("0u");
        }
        if (index + 1 < values) {
            return "packHalf2x16(value" + str(index / 4) + "." + component(index % 4) +
                   component(index % 4 + 1) + ")";
        }
        return "packHalf2x16(vec2(" + value(index) + ", " + value(index + 1) + "))";
    };
    for (int k = 0; k < count; ++k) {
        const int layer = first + k;
        s += "    outLayer" + str(k) + " = uvec4(" + word(4 * layer) + ", " + word(4 * layer + 1) +
             ",\n        " + word(4 * layer + 2) + ", " + word(4 * layer + 3) + ");\n";
    }
    return s + "}\n";
}

std::string weightPassShaderSource(const ShaderLayout& layout) {
    std::string s = kPrecision;
    s += bilinearWeightGlsl();
    s += R"GLSL(
uniform highp sampler2D uUv;             // uv, rows from the top
uniform highp sampler2DArray uWeights;  // the preset's α, one layer per region
)GLSL";
    for (int k = 0; k < layout.alphaLayers(); ++k) {
        s += "layout(location = " + str(k) + ") out vec4 outAlpha" + str(k) + ";\n";
    }
    s += R"GLSL(
void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);  // rows = projector rows, as the geometry buffer
    vec2 uv = texelFetch(uUv, pixel, 0).xy;
)GLSL";
    const std::string wrap = layout.wrapU ? "true" : "false";
    for (int k = 0; k < layout.alphaLayers(); ++k) {
        std::string alphas;
        for (int c = 0; c < 4; ++c) {
            const int r = 4 * k + c;
            alphas += (c == 0 ? "" : ", ") +
                      (r < layout.regions
                           ? "vpeBilinearWeight(uWeights, uv, " + str(r) + ", " + wrap + ")"
                           : std::string("0.0"));
        }
        s += "    outAlpha" + str(k) + " = vec4(" + alphas + ");\n";
    }
    return s + "}\n";
}

std::string reliefPassShaderSource(const ShaderLayout& layout) {
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += reliefStepsGlsl();
    s += bilinearWeightGlsl();
    s += R"GLSL(
uniform highp usampler2D uTracedGeometry1;  // the mesh's shading normal, geometric normal
uniform highp usampler2D uTangents;         // t, b octahedral
uniform highp sampler2D uUv;                // uv, rows from the top
uniform highp sampler2DArray uDetail;       // x, y of the detail normal, one layer per region
uniform highp sampler2DArray uWeights;      // α, one layer per region
uniform int uRegion;  // ≥ 0: that region alone; −1: all, weighted by uWeights
layout(location = 0) out uvec4 outGeometry1;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    uvec4 traced = texelFetch(uTracedGeometry1, pixel, 0);
    vec3 normal = uintBitsToFloat(traced.xyz);
    uvec2 frame = texelFetch(uTangents, pixel, 0).xy;
    vec2 uv = texelFetch(uUv, pixel, 0).xy;
    vec3 detail = vec3(0.0);
)GLSL";
    const std::string wrap = layout.wrapU ? "true" : "false";  // as the material pass
    for (int r = 0; r < layout.regions; ++r) {
        s += "    detail += (uRegion < 0 ? vpeBilinearWeight(uWeights, uv, " + str(r) + ", " +
             wrap + ") : (uRegion == " + str(r) +
             " ? 1.0 : 0.0)) *\n              vpeDetailNormalFromXy(texture(uDetail, vec3(uv, " +
             str(r) + ".0)).xy);\n";
    }
    s += R"GLSL(    if (detail.z > 0.0) {  // else no region weighs here: the mesh's normal
        normal = vpeApplyDetailNormal(vpeOctahedralNormal(frame.x), vpeOctahedralNormal(frame.y),
                                      normal, detail);
    }
    outGeometry1 = uvec4(floatBitsToUint(normal), traced.w);
}
)GLSL";
    return s;
}

std::string passThroughShaderSource(const ShaderLayout& layout, FrameVariant variant) {
    const bool live = variant == FrameVariant::kLive || variant == FrameVariant::kLiveFade;
    const bool fade = variant == FrameVariant::kFade || variant == FrameVariant::kLiveFade;
    std::string s = kPrecision;
    s += frameGeometryUniforms();
    s += "uniform highp sampler2D uThetaTable;\nuniform vec2 uRow;\n";
    if (!layout.measuredLight) {
        s += "uniform highp sampler2D uProjectorLevel;\n";
    }
    if (live) {
        for (int r = 0; r < layout.regions; ++r) {
            s += "uniform highp usampler2DArray uRegionMaterial" + str(r) + ";\n";
        }
        s += "uniform highp sampler2DArray uAlpha;\nuniform highp sampler2DArray uAlphaFrom;\n";
    } else {
        s += "uniform highp usampler2DArray uMaterial;\nuniform highp usampler2DArray "
             "uMaterialFrom;\n";
    }
    if (layout.measuredLight) {
        s += "uniform highp sampler2D uMeasuredIrradiance;  // RGBA16F\n"
             "uniform highp sampler2D uMeasuredFloor;  // RGBA16F\n"
             "uniform highp sampler2D uInverseResponse;  // RGBA16F\n";
    }
    s += R"GLSL(layout(location = 0) out vec4 outLevel;

void main() {
    // The projector's row: y, or (height − ½) − y on a target whose top row is at the top.
    ivec2 pixel = ivec2(gl_FragCoord.x, uRow.x + uRow.y * gl_FragCoord.y);
    vec4 sum = texelFetch(uPosition, pixel, 0);
)GLSL";
    if (layout.measuredLight) {
        s += "    sum += texelFetch(uMeasuredIrradiance, pixel, 0) + "
             "texelFetch(uMeasuredFloor, pixel, 0);\n";
        for (int c = 0; c < 3; ++c) {  // the response inverse: one filtered fetch a channel
            s += "    sum += texture(uInverseResponse, vec2(fract(sum.w * " + str(3 + c) +
                 ".0), 0.5));\n";
        }
    }
    if (!layout.measuredLight) {
        for (int c = 0; c < 3; ++c) {  // the response inverse: one filtered fetch a channel
            s += "    sum += texture(uProjectorLevel, vec2(fract(sum.w * " + str(3 + c) +
                 ".0), 0.5));\n";
        }
    }
    s += R"GLSL(    uvec4 bits = texelFetch(uShading, pixel, 0);
    float x = fract(sum.x * 7.0);  // a table coordinate that varies as θs does
)GLSL";
    for (int r = 0; r < layout.tableRows(); ++r) {
        s += "    sum += texture(uThetaTable, vec2(x, " +
             glslFloat((static_cast<float>(r) + 0.5f) / static_cast<float>(layout.tableRows())) +
             "));\n";
    }
    const auto material = [&](const std::string& sampler) {
        for (int l = 0; l < layout.materialLayers(); ++l) {
            s += "    bits ^= texelFetch(" + sampler + ", ivec3(pixel, " + str(l) + "), 0);\n";
        }
    };
    if (live) {
        for (int k = 0; k < layout.alphaLayers(); ++k) {
            s += "    sum += texelFetch(uAlpha, ivec3(pixel, " + str(k) + "), 0);\n";
            if (fade) {
                s += "    sum += texelFetch(uAlphaFrom, ivec3(pixel, " + str(k) + "), 0);\n";
            }
        }
        for (int r = 0; r < layout.regions; ++r) {
            material("uRegionMaterial" + str(r));
        }
    } else {
        material("uMaterial");
        if (fade) {
            material("uMaterialFrom");
        }
    }
    s += R"GLSL(    outLevel = vec4(fract(sum.xyz + vec3(bits.xyz & 255u) / 255.0), 1.0);
}
)GLSL";
    return s;
}

}  // namespace vpe::renderer::gles
