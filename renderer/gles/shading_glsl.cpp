// SPDX-License-Identifier: MIT
// GLSL mirrors of the frame's C++ steps (see the header).
#include "shading_glsl.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "vpe/proto/half_float.h"
#include "vpe/proto/response_function.h"
#include "vpe/proto/surface_horizon.h"
#include "vpe/proto/viewing_zone.h"
#include "vpe/renderer/cpu/measured_light.h"

namespace vpe::renderer::gles {

std::string glslFloat(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
    std::string literal = text;
    if (literal.find_first_of(".en") == std::string::npos) {
        literal += ".0";
    }
    return literal;
}

std::string shadingStepsGlsl() {
    return "const float VPE_HORIZON_SCALE = " +
           glslFloat(static_cast<float>(1.0 / proto::kHorizonWidth)) + ";\n" +
           "#define VPE_MAX_VIEWING_ZONE " + std::to_string(proto::kMaxViewingZone) + "\n" +
           R"GLSL(
// proto::horizonFactor: smoothstep(0, kHorizonWidth, cosine).
float vpeHorizonFactor(float cosine) {
    float t = clamp(cosine * VPE_HORIZON_SCALE, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// proto::reflectionAngles: (cos θd = n·l, cos θs = 2(n·l)(n·v) − l·v clamped to [−1, 1]).
vec2 vpeReflectionAngles(vec3 normal, vec3 toLight, vec3 toViewer) {
    float nl = dot(normal, toLight);
    float rv = 2.0 * nl * dot(normal, toViewer) - dot(toLight, toViewer);
    return vec2(nl, clamp(rv, -1.0, 1.0));
}

// proto::thetaTableParameter: sin(θs/2)/√2 for cos θs ≥ 0, 1 − cos(θs/2)/√2 below.
float vpeThetaTableParameter(float cosThetaS) {
    float s = sqrt(max(0.5 - 0.5 * abs(cosThetaS), 0.0)) * 0.70710678118654752440;
    return cosThetaS >= 0.0 ? s : 1.0 - s;
}

// The table's texture coordinate, vpeThetaTableParameter(c)·scale + offset with the constants
// folded (scale, offset: a table of N samples maps x to x·(N − 1)/N + ½/N).
float vpeThetaTableCoordinate(float cosThetaS, float scale, float offset) {
    float s = sqrt(max(0.5 - 0.5 * abs(cosThetaS), 0.0)) * (0.70710678118654752440 * scale);
    return cosThetaS >= 0.0 ? offset + s : (scale + offset) - s;
}

// decodeOctahedralNormal.
vec3 vpeOctahedralNormal(uint bits) {
    vec2 e = unpackUnorm2x16(bits) * 2.0 - 1.0;
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float fold = max(-n.z, 0.0);
    n.x += n.x >= 0.0 ? -fold : fold;
    n.y += n.y >= 0.0 ? -fold : fold;
    return normalize(n);
}

// proto::zoneEye: the eye a point is drawn for, the mean direction to the zone's eyes that see
// its side (weighted by the cosine at its geometric normal) at their mean distance; `viewer`
// where none does.
vec3 vpeZoneViewer(vec3 position, vec3 geometric, vec3 viewer, vec3 zone[VPE_MAX_VIEWING_ZONE],
                   int count) {
    vec3 direction = vec3(0.0);
    float weightSum = 0.0;
    float distanceSum = 0.0;
    for (int i = 0; i < count; ++i) {
        vec3 to = zone[i] - position;
        float d = length(to);
        if (!(d > 0.0)) {
            continue;
        }
        float w = dot(geometric, to) / d;
        if (!(w > 0.0)) {
            continue;
        }
        direction += (w / d) * to;
        weightSum += w;
        distanceSum += w * d;
    }
    if (!(weightSum > 0.0)) {
        return viewer;
    }
    return position + (distanceSum / weightSum / length(direction)) * direction;
}

// mirroredViewer: 2(n·v)n − v, fixed per pixel.
vec3 vpeMirroredViewer(vec3 normal, vec3 toViewer) {
    return 2.0 * dot(normal, toViewer) * normal - toViewer;
}

// proto::reflectionAngles from the mirrored viewer m: (cos θd = n·l, cos θs = l·m), cos θs not
// clamped (the table coordinate's max(½ − ½|c|, 0) clips it).
vec2 vpeMirroredReflectionAngles(vec3 normal, vec3 toLight, vec3 mirrored) {
    return vec2(dot(normal, toLight), dot(toLight, mirrored));
}
)GLSL";
}

Vec3d mirroredViewer(const Vec3d& normal, const Vec3d& toViewer) {
    const double nv = 2.0 * (normal.x * toViewer.x + normal.y * toViewer.y + normal.z * toViewer.z);
    return {nv * normal.x - toViewer.x, nv * normal.y - toViewer.y, nv * normal.z - toViewer.z};
}

std::vector<float> projectorLevelTable(const proto::ResponseCurves& response, int samples) {
    const proto::ResponseFunction function = proto::responseFunctionOf(response);
    std::vector<float> table(3 * static_cast<std::size_t>(samples));
    for (int i = 0; i < samples; ++i) {
        const double r = static_cast<double>(i) / static_cast<double>(samples - 1);
        for (int c = 0; c < 3; ++c) {
            // compensatePixel: above 1 → 1, below the black level → 0, else the inverse.
            const double level =
                r >= 1.0 ? 1.0 : (r < function.blackLevel(c) ? 0.0 : function.level(c, r));
            table[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(c)] =
                proto::halfToFloat(proto::floatToHalf(static_cast<float>(level)));
        }
    }
    return table;
}

double projectorLevelFromTable(const std::vector<float>& table, int channel, double relative) {
    const auto samples = static_cast<int>(table.size() / 3);
    const auto at = [&](int i) {
        return static_cast<double>(
            table[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(channel)]);
    };
    // GL_LINEAR at coordinate t = r·(N − 1)/N + ½/N: samples i and i + 1 around t·N − ½ = r·(N −
    // 1).
    const double position = std::clamp(relative, 0.0, 1.0) * static_cast<double>(samples - 1);
    const int i = std::min(static_cast<int>(position), samples - 2);
    const double f = position - static_cast<double>(i);
    return at(i) + (at(i + 1) - at(i)) * f;
}

std::string projectorLevelTableGlsl(int samples) {
    return "const float VPE_LEVEL_OFFSET = " + glslFloat(0.5f / static_cast<float>(samples)) +
           ";\n" + R"GLSL(
uniform highp sampler2D uProjectorLevel;  // RGBA16F cached: the response inverse, 32 KB

// projectorLevelFromTable per channel: scaled = r·(N − 1)/N, one filtered fetch a channel.
vec3 vpeProjectorLevelTable(vec3 scaled) {
    vec3 x = scaled + VPE_LEVEL_OFFSET;
    return vec3(texture(uProjectorLevel, vec2(x.r, 0.5)).r,
                texture(uProjectorLevel, vec2(x.g, 0.5)).g,
                texture(uProjectorLevel, vec2(x.b, 0.5)).b);
}
)GLSL";
}

std::string reliefStepsGlsl() {
    return R"GLSL(
// proto::detailNormalFromXy: z = √(1 − x² − y²), x and y scaled onto the unit disc past it.
vec3 vpeDetailNormalFromXy(vec2 xy) {
    float r2 = dot(xy, xy);
    return r2 > 1.0 ? vec3(xy * inversesqrt(r2), 0.0) : vec3(xy, sqrt(max(1.0 - r2, 0.0)));
}

// proto::applyDetailNormal: normalize(d.x·t + d.y·b + d.z·n).
vec3 vpeApplyDetailNormal(vec3 t, vec3 b, vec3 n, vec3 d) {
    return normalize(d.x * t + d.y * b + d.z * n);
}
)GLSL";
}

std::string bilinearWeightGlsl() {
    return R"GLSL(
// renderer::bilinearFootprint: x = s·width − ½ and y = t·height − ½, clamped to the outermost
// texel centres (or s taken modulo the width: GL_REPEAT), the four taps weighted.
float vpeBilinearWeight(highp sampler2DArray weights, vec2 st, int layer, bool wrapS) {
    ivec2 size = textureSize(weights, 0).xy;
    vec2 x = st * vec2(size) - 0.5;
    int x0, x1;
    float fx;
    if (wrapS) {
        float wrapped = x.x - float(size.x) * floor(x.x / float(size.x));
        x0 = min(int(floor(wrapped)), size.x - 1);
        x1 = x0 + 1 == size.x ? 0 : x0 + 1;
        fx = clamp(wrapped - float(x0), 0.0, 1.0);
    } else {
        float clamped = clamp(x.x, 0.0, float(size.x - 1));
        x0 = int(floor(clamped));
        x1 = min(x0 + 1, size.x - 1);
        fx = clamped - float(x0);
    }
    float y = clamp(x.y, 0.0, float(size.y - 1));
    int y0 = int(floor(y));
    int y1 = min(y0 + 1, size.y - 1);
    float fy = y - float(y0);
    float a = texelFetch(weights, ivec3(x0, y0, layer), 0).r;
    float b = texelFetch(weights, ivec3(x1, y0, layer), 0).r;
    float c = texelFetch(weights, ivec3(x0, y1, layer), 0).r;
    float d = texelFetch(weights, ivec3(x1, y1, layer), 0).r;
    return (1.0 - fx) * (1.0 - fy) * a + fx * (1.0 - fy) * b + (1.0 - fx) * fy * c + fx * fy * d;
}
)GLSL";
}

std::uint32_t encodeOctahedralNormal(const Vec3d& unit) {
    const double sum = std::fabs(unit.x) + std::fabs(unit.y) + std::fabs(unit.z);
    double a = unit.x / sum, b = unit.y / sum;
    if (unit.z < 0) {
        const double foldedA = (1 - std::fabs(b)) * (a >= 0 ? 1 : -1);
        const double foldedB = (1 - std::fabs(a)) * (b >= 0 ? 1 : -1);
        a = foldedA;
        b = foldedB;
    }
    const auto unorm = [](double value) {
        return static_cast<std::uint32_t>(
            std::lround(std::clamp(value * 0.5 + 0.5, 0.0, 1.0) * 65535));
    };
    return unorm(a) | (unorm(b) << 16);
}

Vec3d decodeOctahedralNormal(std::uint32_t packed) {
    // As vpeOctahedralNormal, in float where the shader is (unpackUnorm2x16 divides by 65535).
    const float ex = static_cast<float>(packed & 0xffffu) / 65535.0f * 2.0f - 1.0f;
    const float ey = static_cast<float>(packed >> 16) / 65535.0f * 2.0f - 1.0f;
    float x = ex, y = ey;
    const float z = 1.0f - std::fabs(ex) - std::fabs(ey);
    const float fold = std::max(-z, 0.0f);
    x += x >= 0.0f ? -fold : fold;
    y += y >= 0.0f ? -fold : fold;
    const double dx = x, dy = y, dz = z;
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    return {dx / length, dy / length, dz / length};
}

std::string measuredLightGlsl(int tableSamples) {
    const auto samples = static_cast<float>(tableSamples);
    return "const float VPE_KNEE = " + glslFloat(static_cast<float>(kHighlightKnee)) + ";\n" +
           "const float VPE_RESPONSE_SCALE = " + glslFloat((samples - 1.0f) / samples) + ";\n" +
           "const float VPE_RESPONSE_OFFSET = " + glslFloat(0.5f / samples) + ";\n" +
           R"GLSL(uniform highp sampler2D uInverseResponse;  // RGBA16F cached: g⁻¹ at u = √r

// proto::InverseResponseTable::level per channel: sample i at u = i/(N − 1), at texture
// coordinate (i + ½)/N, so u maps to u·(N − 1)/N + ½/N and the filter interpolates in u.
vec3 vpeMeasuredLevel(vec3 relative) {
    vec3 x = sqrt(clamp(relative, 0.0, 1.0)) * VPE_RESPONSE_SCALE + VPE_RESPONSE_OFFSET;
    return vec3(texture(uInverseResponse, vec2(x.r, 0.5)).r,
                texture(uInverseResponse, vec2(x.g, 0.5)).g,
                texture(uInverseResponse, vec2(x.b, 0.5)).b);
}

// renderer::rollOffHighlight: above the knee, the outputs scaled together so that their
// largest follows κ + (1 − κ)·tanh((t − κ)/(1 − κ)).
vec3 vpeRollOffHighlight(vec3 w) {
    float t = max(w.x, max(w.y, w.z));
    if (t <= VPE_KNEE) {
        return w;
    }
    float span = 1.0 - VPE_KNEE;
    float x = (t - VPE_KNEE) / span;
    // tanh without overflow: 1 − 2/(e^{2x} + 1).
    float rolled = VPE_KNEE + span * (1.0 - 2.0 / (exp(min(2.0 * x, 80.0)) + 1.0));
    return w * (rolled / t);
}

// renderer::compensateMeasuredPixel up to the response inverse: y = (L − D)/F, w = X⁻¹·y, the
// highlight rolled off, negatives raised to 0. A pixel without light in some channel (F ≤ 0)
// gets each primary full where its channel wants light, none elsewhere.
vec3 vpeMeasuredOutputs(vec3 target, vec3 irradiance, vec3 floorLight, mat3 mixingInverse) {
    vec3 wanted = target - floorLight;
    if (any(lessThanEqual(irradiance, vec3(0.0)))) {
        return vec3(greaterThan(wanted, vec3(0.0)));
    }
    return max(vpeRollOffHighlight(mixingInverse * (wanted / irradiance)), 0.0);
}
)GLSL";
}

std::string projectorLevelGlsl(const proto::ResponseCurves& response) {
    if (response.kind != proto::ResponseKind::kCurve) {
        // r(v) = v^γ: black level 0, level = r^(1/γ) on [0, 1]; 1/γ as the CPU takes it.
        std::string inverse;
        for (std::size_t c = 0; c < 3; ++c) {
            inverse += (c == 0 ? "" : ", ") +
                       glslFloat(static_cast<float>(1.0 / static_cast<double>(response.gamma[c])));
        }
        return R"GLSL(
// ResponseFunction::level for this bundle's gamma, with compensatePixel's clipping: the
// clamp does it (above 1 → 1, below 0 → 0^(1/γ) = 0).
vec3 vpeProjectorLevel(vec3 relative) {
    return pow(clamp(relative, 0.0, 1.0), vec3()GLSL" +
               inverse + R"GLSL());
}
)GLSL";
    }
    // A sampled curve, normalized (r(1) = 1): below its first sample (the black level) 0, above
    // 1 full, else the first sample at or above r and the one before, interpolated. The samples
    // are constants: the loop unrolls into compares and selects.
    std::string s =
        "\n// ResponseFunction::level for this bundle's sampled curves.\n"
        "vec3 vpeProjectorLevel(vec3 relative) {\n    vec3 level;\n";
    for (std::size_t c = 0; c < 3; ++c) {
        const std::vector<float>& samples = response.curve[c];
        const float last = samples.back();
        std::string array = "float[" + std::to_string(samples.size()) + "](";
        for (std::size_t k = 0; k < samples.size(); ++k) {
            array += (k == 0 ? "" : ", ") + glslFloat(samples[k] / last);
        }
        array += ")";
        const std::string ch = std::to_string(c);
        s += "    {\n        const float curve[" + std::to_string(samples.size()) + "] = " + array +
             ";\n        float fraction = relative[" + ch + "];\n" +
             "        float previous = curve[0];\n        level[" + ch +
             "] = fraction > 1.0 ? 1.0 : 0.0;\n"
             "        if (fraction > previous && fraction <= 1.0) {\n"
             "            level[" +
             ch +
             "] = 1.0;\n"
             "            for (int k = 1; k < " +
             std::to_string(samples.size()) +
             "; ++k) {\n"
             "                if (curve[k] >= fraction) {\n"
             "                    float f = (fraction - previous) / (curve[k] - previous);\n"
             "                    level[" +
             ch + "] = clamp((float(k - 1) + f) / " + std::to_string(samples.size() - 1) +
             ".0, 0.0, 1.0);\n"
             "                    break;\n                }\n"
             "                previous = curve[k];\n            }\n        }\n    }\n";
    }
    return s + "    return level;\n}\n";
}

}  // namespace vpe::renderer::gles
