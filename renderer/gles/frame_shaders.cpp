// SPDX-License-Identifier: MIT
// GLSL generation for the load passes and the frame (see the header).
#include "frame_shaders.h"

#include <vector>

#include "geometry_buffer.h"
#include "material_codes.h"
#include "shading_glsl.h"
#include "texture_formats.h"

namespace vpe::renderer::gles {

namespace {

const char* const kPrecision = R"GLSL(#version 310 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp usampler2D;
precision highp sampler2DArray;
precision highp usampler2DArray;
precision highp isampler2DArray;
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

// The frame's: X in the object's cube and whether the pixel sees it, the packed shading
// geometry (shading_geometry_pass.h).
std::string frameGeometryUniforms() {
    return "\nuniform highp sampler2D uPosition;" +
           declared(kPositionFormat, "X in the object's cube, 1 on the object in alpha") +
           "uniform highp usampler2D uShading;" +
           declared(kShadingFormat, "n, m = 2(n·v)n − v, g.xy as half floats");
}

// A coded material's two samplers (material_codes.h).
std::string materialUniforms(const std::string& name, const std::string& what) {
    return "uniform highp isampler2DArray u" + name + ";" +
           declared(kMaterialFormat, what + ": the u codes, 1/S and g.z") +
           "uniform highp sampler2D u" + name + "Diffuse;" +
           declared(kDiffuseFormat, what + ": the kd codes");
}

// The expression of material value q of the blended θs maps (`value<layer>.<component>`).
std::string mapValue(int q) {
    return "value" + str(q / 4) + "." + component(q % 4);
}

// Statements fetching coded material `name` at `pixel` (its code words `<prefix>w<layer>`) and
// defining `vec3 <prefix>f`, f in the coding's frame unit (kd's span): kd·cos θd (the kd codes as
// the texture unit decodes them, over [0, 1]) + Σ_j u_j·h'_j, one dot product of a word's four
// codes with a row of the scaled table per channel and row. Needs `angles` and the rows h<r>.
std::string codedMaterial(const ShaderLayout& layout, const std::string& name,
                          const std::string& prefix) {
    std::string s;
    const int layers = layout.materialLayers();
    for (int l = 0; l < layers; ++l) {
        s += "    ivec4 " + prefix + "w" + str(l) + " = texelFetch(u" + name + ", ivec3(pixel, " +
             str(l) + "), 0);\n";
    }
    const auto word = [&](int w) { return prefix + "w" + str(w / 4) + "." + component(w % 4); };
    const int perChannel = basisWordsPerChannel(layout.basisSize);
    s += "    vec3 " + prefix + "f = texelFetch(u" + name +
         "Diffuse, pixel, 0).rgb * angles.x + vec3(";
    for (int c = 0; c < 3; ++c) {
        s += c == 0 ? "" : ",";
        for (int r = 0; r < perChannel; ++r) {
            s += std::string(r == 0 ? "\n        " : " + ") + "dot(vpeSignedBytes(" +
                 word(c * perChannel + r) + "), h" + str(r) + ")";
        }
    }
    s += ")";
    if (layout.diffuseOffset !=
        0.0f) {  // kd's range starts below 0: its low end, the same a channel
        s += " + angles.x * " + glslFloat(layout.diffuseOffset);
    }
    return s + ";\n";
}

// The word after a material's u codes: 1/S and the geometric normal's z, as half floats.
std::string extraWord(const ShaderLayout& layout, const std::string& prefix) {
    const int w = 3 * basisWordsPerChannel(layout.basisSize);
    return "unpackHalf2x16(uint(" + prefix + "w" + str(w / 4) + "." + component(w % 4) + "))";
}

}  // namespace

int ShaderLayout::materialLayers() const {
    return materialCodeLayers(basisSize);
}

const char* frameVariantName(FrameVariant variant) {
    switch (variant) {
        case FrameVariant::kStatic:
            return "static";
        case FrameVariant::kFade:
            return "fade";
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
                              const proto::RenderSettings& settings, bool inverseSquare) {
    const bool fade = variant == FrameVariant::kFade;
    const bool ambient = settings.ambientIrradiance[0] != 0 || settings.ambientIrradiance[1] != 0 ||
                         settings.ambientIrradiance[2] != 0;
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += materialCodesGlsl();
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
    s +=
        "\nuniform highp sampler2D uThetaTable;" +
        declared(kThetaTableFormat, "h_j(x)·step_j/unit, row r holds j = 4r … 4r+3 (linear)", true);
    s +=
        R"GLSL(uniform vec2 uRow;  // (0, 1) on a target whose top row is at its origin, else (H − ½, −1)
uniform vec3 uLightPosition;  // in the object's cube, as the positions (side 1)
// gain · intensity (· π/ρ when assumed) (· d_ref²/side² with 1/d²) · the coding's unit; without
// measured light also · (N − 1)/N, the level table's coordinate scale (vpeProjectorLevelTable),
// as uAmbient.
uniform vec3 uRadianceScale;
uniform vec3 uAmbient;        // room light on the plaster (E_ambient)
uniform float uFade;          // fading: 0 the old material, 1 the new
layout(location = 0) out vec4 outLevel;)GLSL";
    s += declared(kFrameTargetFormat, "the drive levels");
    s += materialUniforms("Material", "the composed material");
    if (fade) {
        s += materialUniforms("MaterialFrom", "fading: the old one");
    }
    s += R"GLSL(
void main() {
    // The projector's row: y, or (height − ½) − y on a target whose top row is at the top.
    ivec2 pixel = ivec2(gl_FragCoord.x, uRow.x + uRow.y * gl_FragCoord.y);
    vec4 position = texelFetch(uPosition, pixel, 0);
    if (position.w == 0.0) {  // sees nothing
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
    vec3 toLight = uLightPosition - position.xyz;  // both in the cube
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
    // f = kd·max(cos θd, 0) + Σ_j u_j h_j(θs) (renderer::evaluateThetaMaterial) in the coding's
    // unit; the max is left out: where cos θd ≤ 0 the horizon factor, which multiplies f, is 0.
    s += codedMaterial(layout, "Material", "to_");
    if (fade) {
        s += codedMaterial(layout, "MaterialFrom", "from_");
        s += "    vec3 f = mix(from_f, to_f, uFade);\n";
    } else {
        s += "    vec3 f = to_f;\n";
    }
    s += "    vec2 extra = " + extraWord(layout, "to_") + ";  // 1/S, g.z\n";
    s += R"GLSL(    vec3 geometric = vec3(s3, extra.y);
    // The light's half of the horizon; the viewer's half is in the material (fixed per pixel).
    float horizon = vpeHorizonFactor(min(angles.x, dot(geometric, l)));
)GLSL";
    const std::string falloff =
        inverseSquare ? " * (inverseLightDistance * inverseLightDistance)" : "";
    if (layout.measuredLight) {
        s += R"GLSL(
    // L = max(gain · H · E · f, 0) (renderer's targetRadiance), then compensateMeasuredPixel
    // with the pixel's measured F and D.
    float irradiance = horizon)GLSL" +
             falloff + R"GLSL(;
    vec3 target = max(uRadianceScale * (irradiance * f), 0.0);
    vec3 relative = vpeMeasuredOutputs(target, texelFetch(uMeasuredIrradiance, pixel, 0).rgb,
                                       texelFetch(uMeasuredFloor, pixel, 0).rgb, uMixingInverse);
    outLevel = vec4(vpeMeasuredLevel(relative), 1.0);
}
)GLSL";
        return s;
    }
    s += R"GLSL(
    // π/ρ·L, L = gain · H · E · f (renderer's targetRadiance), then compensatePixel:
    // r = (π·L/ρ − E_ambient) / S, the uniforms scaled by (N − 1)/N: the level table's
    // coordinate less its offset. targetRadiance's max(L, 0) is the table's: below r = 0 its
    // clamped edge is level 0, where max(L, 0) − E_ambient ≤ 0 leads too.
    float inverseScale = extra.x;
)GLSL";
    // With room light: (gain·H·f·π/ρ − E_ambient)·(1/S), one multiply by 1/S a channel where
    // scaling both terms by it takes two.
    s += ambient ? "    vec3 wanted = (f * (uRadianceScale * (horizon" + falloff +
                       ")) - uAmbient) * inverseScale;\n"
                 : "    vec3 wanted = f * (uRadianceScale * (horizon * inverseScale" + falloff +
                       "));\n";
    s += R"GLSL(    outLevel = vec4(vpeProjectorLevelTable(wanted), 1.0);
}
)GLSL";
    return s;
}

std::string materialPassShaderSource(const ShaderLayout& layout, int first, int count,
                                     bool diffuse) {
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += bilinearWeightGlsl();
    s += materialCodesGlsl();
    s += geometryUniforms();
    for (int r = 0; r < layout.regions; ++r) {
        s += "uniform highp sampler2DArray uThetaMap" + str(r) +
             ";  // RGBA16F, texture space, 4 values a layer\n";
    }
    s += R"GLSL(uniform highp sampler2DArray uWeights;  // α, one layer per region
uniform int uRegion;  // ≥ 0: that region alone; −1: all, weighted by uWeights
uniform vec3 uViewer;
uniform vec3 uZone[VPE_MAX_VIEWING_ZONE];  // the viewing zone's eyes (ViewerEyes)
uniform int uZoneCount;
uniform float uDiffuseLow;    // the coding (material_codes.h): kd's low end,
uniform float uDiffuseScale;  // 1023 / its span,
uniform float uInverseBasisStep[)GLSL" +
         str(layout.basisSize) + R"GLSL(];  // and 1 / step_j (0 where every u_j is 0)
)GLSL";
    for (int k = 0; k < count; ++k) {
        s += "layout(location = " + str(k) + ") out ivec4 outLayer" + str(k) + ";\n";
    }
    if (diffuse) {
        s += "layout(location = " + str(count) + ") out vec4 outDiffuse;\n";
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
        geometric = vpeOctahedralNormal(geometry1.w);
        vec3 eye = vpeZoneViewer(geometry0.xyz, geometric, uViewer, uZone, uZoneCount);
        vec3 v = normalize(eye - geometry0.xyz);
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
    // Value i of the blended θs maps: kd RGB, then u_j RGB.
    for (int l = 0; l < layout.mapLayers(); ++l) {
        std::string sum;
        for (int r = 0; r < layout.regions; ++r) {
            sum += (r == 0 ? "" : " + ") + std::string("alpha") + str(r) + " * texture(uThetaMap" +
                   str(r) + ", vec3(uv, " + str(l) + ".0))";
        }
        s += "    vec4 value" + str(l) + " = " + sum + ";\n";
    }
    // Word w of the codes: u_j of channel c in byte j % 4 of word c·W + j/4, then 1/S and g.z.
    const int perChannel = basisWordsPerChannel(layout.basisSize);
    const auto word = [&](int w) -> std::string {
        if (w == 3 * perChannel) {
            // 1/S within the half floats' range: kNoProjectorLight becomes their largest, 65504.
            return "int(packHalf2x16(vec2(min(geometry0.w, 65504.0), geometric.z)))";
        }
        if (w > 3 * perChannel) {
            return "0";
        }
        const int c = w / perChannel, row = w % perChannel;
        std::string codes = "vec4(";
        for (int b = 0; b < 4; ++b) {
            const int j = 4 * row + b;
            codes += b == 0 ? "" : ", ";
            codes += j < layout.basisSize
                         ? mapValue(3 + 3 * j + c) + " * uInverseBasisStep[" + str(j) + "]"
                         : std::string("0.0");
        }
        return "vpePackSignedBytes(clamp(floor(" + codes + ") + 0.5), -127.0, 127.0))";
    };
    for (int k = 0; k < count; ++k) {
        const int layer = first + k;
        s += "    outLayer" + str(k) + " = ivec4(" + word(4 * layer) + ",\n        " +
             word(4 * layer + 1) + ",\n        " + word(4 * layer + 2) + ",\n        " +
             word(4 * layer + 3) + ");\n";
    }
    if (diffuse) {
        s += "    vec3 diffuse = clamp(floor((vec3(" + mapValue(0) + ", " + mapValue(1) + ", " +
             mapValue(2) + R"GLSL() - uDiffuseLow) * uDiffuseScale + 0.5), 0.0, 1023.0);
    outDiffuse = vec4(diffuse / 1023.0, 1.0);
)GLSL";
    }
    return s + "}\n";
}

std::string composePassShaderSource(const ShaderLayout& layout, int first, int count,
                                    bool diffuse) {
    std::string s = kPrecision;
    s += materialCodesGlsl();
    for (int r = 0; r < layout.regions; ++r) {
        s += "uniform highp isampler2DArray uRegion" + str(r) + ";" +
             declared(kMaterialFormat, "region " + str(r) + "'s codes");
        s += "uniform highp sampler2D uRegion" + str(r) + "Diffuse;" +
             declared(kDiffuseFormat, "its kd codes");
    }
    s += "uniform highp sampler2DArray uAlpha;" +
         declared(alphaFormat(layout.regions), "the preset's α, four regions a layer") +
         "uniform float uDiffuseLow;  // the coding's kd low end over its span\n";
    for (int k = 0; k < count; ++k) {
        s += "layout(location = " + str(k) + ") out ivec4 outLayer" + str(k) + ";" +
             declared(kMaterialFormat, "the blend's codes");
    }
    if (diffuse) {
        s += "layout(location = " + str(count) + ") out vec4 outDiffuse;" +
             declared(kDiffuseFormat, "its kd codes");
    }
    s += R"GLSL(
void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
)GLSL";
    for (int k = 0; k < layout.alphaLayers(); ++k) {
        s += "    vec4 alphas" + str(k) + " = texelFetch(uAlpha, ivec3(pixel, " + str(k) +
             "), 0);\n";
    }
    std::string alphaSum;
    for (int r = 0; r < layout.regions; ++r) {
        s += "    float alpha" + str(r) + " = alphas" + str(r / 4) + "." + component(r % 4) + ";\n";
        alphaSum += (r == 0 ? "" : " + ") + std::string("alpha") + str(r);
    }
    const int perChannel = basisWordsPerChannel(layout.basisSize);
    for (int k = 0; k < count; ++k) {
        const int layer = first + k;
        for (int r = 0; r < layout.regions; ++r) {
            s += "    ivec4 r" + str(r) + "_" + str(k) + " = texelFetch(uRegion" + str(r) +
                 ", ivec3(pixel, " + str(layer) + "), 0);\n";
        }
        std::string words;
        for (int c = 0; c < 4; ++c) {
            const int w = 4 * layer + c;
            std::string value;
            if (w < 3 * perChannel) {
                std::string blend;
                for (int r = 0; r < layout.regions; ++r) {
                    blend += (r == 0 ? "" : " + ") + std::string("alpha") + str(r) +
                             " * vpeSignedBytes(r" + str(r) + "_" + str(k) + "." + component(c) +
                             ")";
                }
                value = "vpePackSignedBytes(clamp(floor(" + blend + " + 0.5), -127.0, 127.0))";
            } else {
                value = "r0_" + str(k) + "." + component(c);  // 1/S and g.z: every region's
            }
            words += (c == 0 ? "" : ",\n        ") + value;
        }
        s += "    outLayer" + str(k) + " = ivec4(" + words + ");\n";
    }
    if (diffuse) {
        // kd = low + span·t per region: Σ α_r kd_r = low·Σα + span·Σ α_r t_r, as a code again.
        std::string blend;
        for (int r = 0; r < layout.regions; ++r) {
            blend += (r == 0 ? "" : " + ") + std::string("alpha") + str(r) +
                     " * texelFetch(uRegion" + str(r) + "Diffuse, pixel, 0).rgb";
        }
        s += "    vec3 diffuse = clamp(floor((" + blend + " + uDiffuseLow * (" + alphaSum +
             " - 1.0)) * 1023.0 + 0.5), 0.0, 1023.0);\n";
        s += "    outDiffuse = vec4(diffuse / 1023.0, 1.0);\n";
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
    const bool fade = variant == FrameVariant::kFade;
    std::string s = kPrecision;
    s += frameGeometryUniforms();
    s += "uniform highp sampler2D uThetaTable;\nuniform vec2 uRow;\n";
    if (!layout.measuredLight) {
        s += "uniform highp sampler2D uProjectorLevel;\n";
    }
    s += "uniform highp isampler2DArray uMaterial;\nuniform highp sampler2D uMaterialDiffuse;\n";
    if (fade) {
        s += "uniform highp isampler2DArray uMaterialFrom;\n"
             "uniform highp sampler2D uMaterialFromDiffuse;\n";
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
    const std::string response = layout.measuredLight ? "uInverseResponse" : "uProjectorLevel";
    if (layout.measuredLight) {
        s += "    sum += texelFetch(uMeasuredIrradiance, pixel, 0) + "
             "texelFetch(uMeasuredFloor, pixel, 0);\n";
    }
    for (int c = 0; c < 3; ++c) {  // the response inverse: one filtered fetch a channel
        s += "    sum += texture(" + response + ", vec2(fract(sum.w * " + str(3 + c) +
             ".0), 0.5));\n";
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
            s += "    bits ^= uvec4(texelFetch(" + sampler + ", ivec3(pixel, " + str(l) +
                 "), 0));\n";
        }
        s += "    sum += texelFetch(" + sampler + "Diffuse, pixel, 0);\n";
    };
    material("uMaterial");
    if (fade) {
        material("uMaterialFrom");
    }
    s += R"GLSL(    outLevel = vec4(fract(sum.xyz + vec3(bits.xyz & 255u) / 255.0), 1.0);
}
)GLSL";
    return s;
}

}  // namespace vpe::renderer::gles
