// SPDX-License-Identifier: MIT
// GLSL generation for the material pass and the frame (see the header).
#include "vpe/renderer/gles/frame_shaders.h"

#include <vector>

#include "vpe/renderer/gles/geometry_buffer.h"
#include "vpe/renderer/gles/shading_glsl.h"

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

const char* const kGeometryUniforms = R"GLSL(
uniform highp sampler2D uGeometry0;   // X, 1/S (geometry_buffer.h)
uniform highp usampler2D uGeometry1;  // shading normal (float bits), geometric normal (octahedral)
uniform highp sampler2D uUv;          // uv, rows from the top
)GLSL";

// Statements fetching material `sampler` at `pixel` and naming its values: half floats, two a
// word, eight a layer, in thetaMaterialSize order.
std::string unpackMaterial(const ShaderLayout& layout, const std::string& sampler,
                           const std::string& prefix) {
    std::string s;
    for (int l = 0; l < layout.materialLayers(); ++l) {
        s += "    uvec4 " + prefix + "w" + str(l) + " = texelFetch(" + sampler + ", ivec3(pixel, " +
             str(l) + "), 0);\n";
    }
    for (int word = 0; 2 * word < layout.materialValues(); ++word) {
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
        s += projectorLevelGlsl(settings.response);
    } else {
        s += measuredLightGlsl(kInverseResponseSamples);
        s += R"GLSL(uniform highp sampler2D uMeasuredIrradiance;  // RGBA16F: F per projector pixel
uniform highp sampler2D uMeasuredFloor;       // RGBA16F: D per projector pixel
uniform mat3 uMixingInverse;                  // X⁻¹
)GLSL";
    }
    s += kGeometryUniforms;
    s += R"GLSL(
uniform highp sampler2D uThetaTable;  // h_j(x), row r holds j = 4r … 4r+3 (linear)
uniform bool uTopRowAtOrigin;
uniform int uHeight;
uniform vec3 uLightPosition;
uniform vec3 uViewer;
uniform vec3 uRadianceScale;  // gain · intensity (· π/ρ when assumed) (· d_ref² with 1/d²)
uniform float uFalloff;       // 1: inverse-square falloff, 0: none
uniform vec3 uAmbient;        // room light on the plaster (E_ambient)
uniform float uFade;          // fading: 0 the old material or weights, 1 the new
layout(location = 0) out vec4 outLevel;
)GLSL";
    if (live) {
        for (int r = 0; r < layout.regions; ++r) {
            s += "uniform highp usampler2DArray uRegionMaterial" + str(r) + ";\n";
        }
        s += "uniform highp sampler2DArray uWeights;      // α, one layer per region\n";
        s += "uniform highp sampler2DArray uWeightsFrom;  // fading: the old preset's α\n";
    } else {
        s += "uniform highp usampler2DArray uMaterial;      // the composed material\n";
        s += "uniform highp usampler2DArray uMaterialFrom;  // fading: the old one\n";
    }
    s += R"GLSL(
void main() {
    ivec2 pixel = ivec2(int(gl_FragCoord.x),
                        uTopRowAtOrigin ? int(gl_FragCoord.y) : uHeight - 1 - int(gl_FragCoord.y));
    vec4 geometry0 = texelFetch(uGeometry0, pixel, 0);
    float inverseScale = geometry0.w;
    if (inverseScale < 0.0) {  // sees nothing
        outLevel = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 position = geometry0.xyz;
    uvec4 geometry1 = texelFetch(uGeometry1, pixel, 0);
    vec3 normal = uintBitsToFloat(geometry1.xyz);
    vec3 geometric = vpeOctahedralNormal(geometry1.w);
    vec3 toLight = uLightPosition - position;
    float inverseLightDistance = inversesqrt(dot(toLight, toLight));
    vec3 l = toLight * inverseLightDistance;
    vec3 toViewer = uViewer - position;
    vec3 v = toViewer * inversesqrt(dot(toViewer, toViewer));
    vec2 angles = vpeReflectionAngles(normal, l, v);
    // The light's half of the horizon; the viewer's half is in the material (fixed per pixel).
    float horizon = vpeHorizonFactor(angles.x) * vpeHorizonFactor(dot(geometric, l));
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
    // The material: value q of the (blended) codes.
    std::vector<std::string> m(static_cast<std::size_t>(values));
    if (live) {
        s += "    vec2 uv = texelFetch(uUv, pixel, 0).xy;\n";
        for (int r = 0; r < layout.regions; ++r) {
            const std::string alpha = "texture(uWeights, vec3(uv, " + str(r) + ".0)).r";
            s += "    float alpha" + str(r) + " = " +
                 (fade ? "mix(texture(uWeightsFrom, vec3(uv, " + str(r) + ".0)).r, " + alpha +
                             ", uFade)"
                       : alpha) +
                 ";\n";
            s += unpackMaterial(layout, "uRegionMaterial" + str(r), "r" + str(r) + "_");
        }
        for (int q = 0; q < values; ++q) {
            std::string sum;
            for (int r = 0; r < layout.regions; ++r) {
                sum += (r == 0 ? "" : " + ") + std::string("alpha") + str(r) + " * " +
                       unpacked("r" + str(r) + "_", q);
            }
            m[static_cast<std::size_t>(q)] = "(" + sum + ")";
        }
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
    }
    if (live || fade) {  // blend once into plain floats, then evaluate
        for (int q = 0; q < values; ++q) {
            s += "    float m" + str(q) + " = " + m[static_cast<std::size_t>(q)] + ";\n";
            m[static_cast<std::size_t>(q)] = "m" + str(q);
        }
    }
    const auto rgb = [&](int term) {
        return "vec3(" + m[static_cast<std::size_t>(3 * term)] + ", " +
               m[static_cast<std::size_t>(3 * term + 1)] + ", " +
               m[static_cast<std::size_t>(3 * term + 2)] + ")";
    };
    // f = kd·max(cos θd, 0) + Σ_j u_j h_j(θs)  (renderer::evaluateThetaMaterial)
    s += "    vec3 f = " + rgb(0) + " * max(angles.x, 0.0)";
    for (int j = 0; j < layout.basisSize; ++j) {
        s += "\n        + " + rgb(1 + j) + " * h" + str(j / 4) + "." + component(j % 4);
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
    // r = (π·L/ρ − E_ambient) / S (S = 0: 1/S is kNoProjectorLight, clipping either way).
    float irradiance = horizon * mix(1.0, inverseLightDistance * inverseLightDistance, uFalloff);
    vec3 wanted = max(uRadianceScale * (irradiance * f), 0.0))GLSL";
    s += ambient ? " - uAmbient;\n" : ";\n";
    s += R"GLSL(    vec3 relative = wanted * inverseScale;
    outLevel = vec4(vpeProjectorLevel(relative), 1.0);
}
)GLSL";
    return s;
}

std::string materialPassShaderSource(const ShaderLayout& layout, int first, int count) {
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += kGeometryUniforms;
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
    if (geometry0.w >= 0.0) {  // sees the object
        uvec4 geometry1 = texelFetch(uGeometry1, pixel, 0);
        vec3 v = normalize(uViewer - geometry0.xyz);
        viewerHorizon = vpeHorizonFactor(dot(uintBitsToFloat(geometry1.xyz), v)) *
                        vpeHorizonFactor(dot(vpeOctahedralNormal(geometry1.w), v));
        uv = texelFetch(uUv, pixel, 0).xy;
    }
)GLSL";
    for (int r = 0; r < layout.regions; ++r) {
        s += "    float alpha" + str(r) +
             " = viewerHorizon * (uRegion < 0 ? texture(uWeights, vec3(uv, " + str(r) +
             ".0)).r : (uRegion == " + str(r) + " ? 1.0 : 0.0));\n";
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
    const auto word = [&](int w) {
        const int index = 2 * w;
        if (index >= layout.materialValues()) {
            return std::string("0u");
        }
        const std::string pair =
            "value" + str(index / 4) + "." + component(index % 4) + component(index % 4 + 1);
        return "packHalf2x16(" + pair + ")";
    };
    for (int k = 0; k < count; ++k) {
        const int layer = first + k;
        s += "    outLayer" + str(k) + " = uvec4(" + word(4 * layer) + ", " + word(4 * layer + 1) +
             ",\n        " + word(4 * layer + 2) + ", " + word(4 * layer + 3) + ");\n";
    }
    return s + "}\n";
}

std::string reliefPassShaderSource(const ShaderLayout& layout) {
    std::string s = kPrecision;
    s += shadingStepsGlsl();
    s += reliefStepsGlsl();
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
    for (int r = 0; r < layout.regions; ++r) {
        s += "    detail += (uRegion < 0 ? texture(uWeights, vec3(uv, " + str(r) +
             ".0)).r : (uRegion == " + str(r) +
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
    s += kGeometryUniforms;
    s += "uniform highp sampler2D uThetaTable;\nuniform bool uTopRowAtOrigin;\nuniform int "
         "uHeight;\n";
    if (live) {
        for (int r = 0; r < layout.regions; ++r) {
            s += "uniform highp usampler2DArray uRegionMaterial" + str(r) + ";\n";
        }
        s += "uniform highp sampler2DArray uWeights;\nuniform highp sampler2DArray uWeightsFrom;\n";
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
    ivec2 pixel = ivec2(int(gl_FragCoord.x),
                        uTopRowAtOrigin ? int(gl_FragCoord.y) : uHeight - 1 - int(gl_FragCoord.y));
    vec4 sum = texelFetch(uGeometry0, pixel, 0);
)GLSL";
    if (layout.measuredLight) {
        s += "    sum += texelFetch(uMeasuredIrradiance, pixel, 0) + "
             "texelFetch(uMeasuredFloor, pixel, 0);\n";
        for (int c = 0; c < 3; ++c) {  // the response inverse: one filtered fetch a channel
            s += "    sum += texture(uInverseResponse, vec2(fract(sum.w * " + str(3 + c) +
                 ".0), 0.5));\n";
        }
    }
    s += R"GLSL(    uvec4 bits = texelFetch(uGeometry1, pixel, 0);
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
        s += "    vec2 uv = texelFetch(uUv, pixel, 0).xy;\n";
        for (int r = 0; r < layout.regions; ++r) {
            s += "    sum.x += texture(uWeights, vec3(uv, " + str(r) + ".0)).r;\n";
            if (fade) {
                s += "    sum.x += texture(uWeightsFrom, vec3(uv, " + str(r) + ".0)).r;\n";
            }
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
