// SPDX-License-Identifier: MIT
// GlesFrameRenderer: upload, shader generation and the two passes (see the header).
#include "vpe/renderer/gles/gles_frame_renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <span>
#include <stdexcept>
#include <utility>

#include <GLES3/gl31.h>

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/fourier_brdf.h"
#include "vpe/renderer/gles/fourier_brdf_glsl.h"
#include "vpe/renderer/pinhole_camera.h"

namespace vpe::renderer::gles {

namespace {

// The mesh as a table of triangles, kTriangleTexels RGBA32F texels each (see kCommonGlsl),
// kTrianglesPerRow a row: rows of 2046 texels fit ES 3.1's smallest GL_MAX_TEXTURE_SIZE.
constexpr int kTriangleTexels = 6;
constexpr int kTrianglesPerRow = 341;
static_assert(kTriangleTexels == 6 && kTrianglesPerRow == 341,
              "vpeTriangleTexel (kCommonGlsl) hard-codes the triangle table's layout");
// Texture units.
constexpr int kUnitIds = 0, kUnitTriangles = 1, kUnitRays = 2, kUnitWeights = 3, kUnitCurve = 4,
              kUnitRegions = 5;
// Pixels added around each triangle's cover (box or grown triangle, see kVisibilityVertex):
// pixel centres on an edge (the rasterizer's tie rule would drop some), float rounding, and any
// bend the sampled edge points miss. The frame tests pass with 0.02 and fail with 0.
constexpr float kCoverMarginPixels = 1.0f;

const char* const kCommonGlsl = R"GLSL(
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp usampler2D;
precision highp sampler2DArray;

uniform highp sampler2D uTriangles; // RGBA32F: the triangle table (vpeTriangleTexel)
uniform vec2 uSize;                 // projector width, height
uniform bool uTopRowAtOrigin;       // GL row 0 is the projector's top row
uniform mat3 uRt;                   // Rᵀ (R uploaded row-major without transposing)
uniform vec3 uT;                    // T
uniform vec3 uCenter;               // −Rᵀ·T

// Texel k of triangle t, 341 triangles a row. Texels 0–2: the vertices' positions p0, p1, p2;
// 3–5: their normals n0, n1, n2; the w components hold the uvs, u0 v0 u1 v1 u2 v2. One fetch per
// texel and no index indirection: fetches are what costs most on llvmpipe and on the Pi's TMU.
vec4 vpeTriangleTexel(int t, int k) {
    return texelFetch(uTriangles, ivec2(6 * (t % 341) + k, t / 341), 0);
}


// Möller–Trumbore as the CPU ray caster: (t, b1, b2) of the ray origin + t·direction.
vec3 vpeIntersect(vec3 origin, vec3 direction, vec3 p0, vec3 p1, vec3 p2, out bool hit) {
    vec3 e1 = p1 - p0;
    vec3 e2 = p2 - p0;
    vec3 p = cross(direction, e2);
    float det = dot(e1, p);
    hit = det != 0.0;
    float invDet = 1.0 / (det == 0.0 ? 1e-30 : det);
    vec3 s = origin - p0;
    float b1 = dot(s, p) * invDet;
    vec3 q = cross(s, e1);
    float b2 = dot(direction, q) * invDet;
    float t = dot(e2, q) * invDet;
    const float slack = 1e-5;  // float rounding; the CPU's slack is 1e-9 in double
    hit = hit && b1 >= -slack && b1 <= 1.0 + slack && b2 >= -slack && b1 + b2 <= 1.0 + slack &&
          t > 0.0;
    return vec3(t, b1, b2);
}
)GLSL";

// Fragment stages: the projector pixel (x, y) (row 0 the top row) of a fragment.
const char* const kPixelGlsl = R"GLSL(
ivec2 vpePixel() {
    int x = int(gl_FragCoord.x);
    int y = int(gl_FragCoord.y);
    return ivec2(x, uTopRowAtOrigin ? y : int(uSize.y) - 1 - y);
}
)GLSL";

const char* const kVisibilityVertex = R"GLSL(
uniform vec4 uIntrinsics;  // fx, fy, cx, cy
uniform float uSkew;
uniform float uDistortion[5];  // k1, k2, p1, p2, k3
uniform float uMargin;
flat out highp uint vTriangle;

// renderer::distortNormalized then K: the pixel of a camera-frame point.
vec2 vpeProjectPixel(vec3 x) {
    float a = x.x / x.z, b = x.y / x.z;
    float r2 = a * a + b * b;
    float radial = 1.0 + uDistortion[0] * r2 + uDistortion[1] * r2 * r2 +
                   uDistortion[4] * r2 * r2 * r2;
    float ad = a * radial + 2.0 * uDistortion[2] * a * b + uDistortion[3] * (r2 + 2.0 * a * a);
    float bd = b * radial + uDistortion[2] * (r2 + 2.0 * b * b) + 2.0 * uDistortion[3] * a * b;
    return vec2(uIntrinsics.x * ad + uSkew * bd + uIntrinsics.z, uIntrinsics.y * bd + uIntrinsics.w);
}

// The ray test's per-triangle constants (see vpeIntersect): with s = C − p0 the same for every
// pixel's ray, Möller–Trumbore's scalar triple products become dot products of the ray
// direction d with vectors of the triangle: det = e1·(d × e2) = d·(e2 × e1),
// b1·det = s·(d × e2) = d·(e2 × s), b2·det = d·(s × e1), t·det = e2·(s × e1).
flat out vec3 vDet;
flat out vec3 vB1;
flat out vec3 vB2;
flat out float vT;

// The offset line {X : dot(X, normal) = offset} of each edge; the corner where two meet.
vec2 vpeMeet(vec3 a, vec3 b) {
    float det = a.x * b.y - a.y * b.x;
    return vec2(a.z * b.y - b.z * a.y, a.x * b.z - b.x * a.z) / det;
}

void main() {
    int triangle = gl_VertexID / 6;
    int corner = gl_VertexID % 6;
    vec3 p[3] = vec3[3](vpeTriangleTexel(triangle, 0).xyz, vpeTriangleTexel(triangle, 1).xyz,
                        vpeTriangleTexel(triangle, 2).xyz);
    vec3 e1 = p[1] - p[0], e2 = p[2] - p[0], s = uCenter - p[0];
    vec3 q = cross(s, e1);
    vDet = cross(e2, e1);
    vB1 = cross(e2, s);
    vB2 = q;
    vT = dot(e2, q);
    vTriangle = uint(triangle);

    // The vertices and three points along each edge (edge e from vertex e to e + 1), projected
    // with distortion: a straight edge bends.
    vec2 points[12];
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    bool behind = false;
    for (int e = 0; e < 3; ++e) {
        for (int k = 0; k < 4; ++k) {
            vec3 x = mix(p[e], p[(e + 1) % 3], float(k) * 0.25) * uRt + uT;  // R·X + T
            behind = behind || x.z <= 1e-6;
            points[4 * e + k] = x.z > 1e-6 ? vpeProjectPixel(x) : vec2(0.0);
            lo = min(lo, points[4 * e + k]);
            hi = max(hi, points[4 * e + k]);
        }
    }
    vec2 pixel;
    if (behind) {  // crosses the projector's plane: let every pixel test its ray
        pixel = vec2((corner == 1 || corner == 4 || corner == 5) ? uSize.x + 1.0 : -2.0,
                     (corner == 2 || corner == 3 || corner == 5) ? uSize.y + 1.0 : -2.0);
    } else {
        // The smaller of two covers of the distorted triangle: the triangle of its edges'
        // chords each pushed out by the edge's outward bend (measured at the three points, with
        // a quarter more for the bend between them), or the box of the twelve points grown by a
        // quarter of the largest bend (a curve strays from the chord between two neighbouring
        // points by ~1/16 of its bend). Both grown by the margin (ties, float rounding).
        vec2 v0 = points[0], v1 = points[4], v2 = points[8];
        float orientation = sign((v1.x - v0.x) * (v2.y - v0.y) - (v1.y - v0.y) * (v2.x - v0.x));
        vec3 lines[3];
        float largestBend = 0.0;
        bool valid = orientation != 0.0;
        for (int e = 0; e < 3; ++e) {
            vec2 from = points[4 * e], to = points[(4 * e + 4) % 12];
            vec2 along = to - from;
            float length_ = length(along);
            valid = valid && length_ > 0.0;
            // Outward: to the right of the edge for a counter-clockwise (y up) orientation.
            vec2 normal = orientation * vec2(along.y, -along.x) / max(length_, 1e-30);
            float bend = 0.0;
            for (int k = 1; k < 4; ++k) {
                float deviation = dot(points[4 * e + k] - from, normal);
                bend = max(bend, deviation);
                largestBend = max(largestBend, abs(deviation));
            }
            lines[e] = vec3(normal, dot(from, normal) + 1.25 * bend + uMargin);
        }
        vec2 boxLo = lo - uMargin - 0.25 * largestBend, boxHi = hi + uMargin + 0.25 * largestBend;
        float boxArea = (boxHi.x - boxLo.x) * (boxHi.y - boxLo.y);
        vec2 d0 = vpeMeet(lines[2], lines[0]);
        vec2 d1 = vpeMeet(lines[0], lines[1]);
        vec2 d2 = vpeMeet(lines[1], lines[2]);
        float area = 0.5 * abs((d1.x - d0.x) * (d2.y - d0.y) - (d1.y - d0.y) * (d2.x - d0.x));
        valid = valid && !isinf(area) && !isnan(area) && area < boxArea;
        if (valid) {
            pixel = corner == 0 ? d0 : corner == 1 ? d1 : corner == 2 ? d2 : d0;  // 3–5: empty
        } else {
            boxLo = max(boxLo, vec2(-2.0));
            boxHi = min(boxHi, uSize + 1.0);
            pixel = vec2((corner == 1 || corner == 4 || corner == 5) ? boxHi.x : boxLo.x,
                         (corner == 2 || corner == 3 || corner == 5) ? boxHi.y : boxLo.y);
        }
    }
    // Pixel centres at integers; GL window coordinates put them at + 0.5.
    vec2 window = vec2(pixel.x + 0.5, uTopRowAtOrigin ? pixel.y + 0.5 : uSize.y - 0.5 - pixel.y);
    gl_Position = vec4(window / uSize * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";

const char* const kVisibilityFragment = R"GLSL(
uniform highp sampler2D uRays;  // RG32F: undistorted (a, b) of each pixel centre, row 0 top
uniform float uDepthScale;
flat in highp uint vTriangle;
flat in vec3 vDet;
flat in vec3 vB1;
flat in vec3 vB2;
flat in float vT;
layout(location = 0) out highp uint outTriangle;

void main() {
    vec2 ab = texelFetch(uRays, vpePixel(), 0).xy;
    vec3 direction = uRt * vec3(ab, 1.0);
    // vpeIntersect with the triangle's constants (the vertex shader's vDet …).
    float det = dot(direction, vDet);
    float invDet = 1.0 / (det == 0.0 ? 1e-30 : det);
    float b1 = dot(direction, vB1) * invDet;
    float b2 = dot(direction, vB2) * invDet;
    float t = vT * invDet;
    const float slack = 1e-5;
    if (!(det != 0.0 && b1 >= -slack && b1 <= 1.0 + slack && b2 >= -slack &&
          b1 + b2 <= 1.0 + slack && t > 0.0)) {
        discard;
    }
    gl_FragDepth = clamp(t * uDepthScale, 0.0, 1.0);
    outTriangle = vTriangle + 1u;
}
)GLSL";

const char* const kFullScreenVertex = R"GLSL(#version 310 es
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";

// A float as a GLSL literal that reads back as the same float (9 significant digits).
std::string glslFloat(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
    std::string literal = text;
    if (literal.find_first_of(".e") == std::string::npos) {
        literal += ".0";
    }
    return literal;
}

// Value i of a texel (3·k + channel) in the vec4 layers c0, c1, …: "c<i/4>.<xyzw[i%4]>".
std::string layerComponent(const std::string& prefix, int i) {
    return prefix + std::to_string(i / 4) + "." + "xyzw"[i % 4];
}

// GLSL adding region r's contribution α_r·f_r to `f`: straight-line code for this bundle, so
// that no array is ever indexed dynamically (llvmpipe spilled those to memory) and no constant
// is loaded from a buffer. Full coefficients: f_r = Σ_k c_k·basis[k], c_k the bilinear texel.
// Low rank, the BRDF evaluated in the low-rank space, the mean and basis baked in as constants:
// f_r = μ·basis + Σ_j w_j (B_j·basis), w the bilinear code — the same value as expanding
// μ + Σ_j w_j B_j first (the BRDF is linear in the coefficients), ~3% faster on llvmpipe.
std::string regionBrdfGlsl(const proto::BundleView& bundle, std::size_t r, bool hasWeights) {
    const proto::CoefficientMapView& map = bundle.regions()[r].coefficients;
    const int coefficients = proto::coefficientCount(bundle.model().harmonics);
    const int values = bundle.model().coefficientsPerTexel();
    const std::string n = std::to_string(r);
    std::string s = "        {\n";
    s += hasWeights ? "            float alpha = texture(uWeights, vec3(uv, " + n + ".0)).r;\n"
                    : "            float alpha = 1.0;\n";
    const bool lowRank = map.encoding == proto::CoefficientEncoding::kLowRank;
    const std::string prefix = lowRank ? "w" : "c";  // the code w or the coefficients c
    for (int l = 0; l < map.layers.layers; ++l) {
        s += "            vec4 " + prefix + std::to_string(l) + " = texture(uRegion" + n +
             ", vec3(uv, " + std::to_string(l) + ".0));\n";
    }
    // Σ_k value(k)·basis[k], value(k) the RGB of coefficient k (bundleCoefficientIndex(k, c)).
    const auto brdf = [&](const std::function<std::string(int)>& value) {
        std::string sum;
        for (int k = 0; k < coefficients; ++k) {
            std::array<int, 3> rgb{};
            for (int c = 0; c < 3; ++c) {
                rgb[static_cast<std::size_t>(c)] = proto::bundleCoefficientIndex(k, c);
            }
            sum += std::string(k == 0 ? "" : "\n                + ") + "vec3(" + value(rgb[0]) +
                   ", " + value(rgb[1]) + ", " + value(rgb[2]) + ") * basis[" + std::to_string(k) +
                   "]";
        }
        return sum;
    };
    if (!lowRank) {
        s += "            vec3 region = " + brdf([](int i) { return layerComponent("c", i); }) +
             ";\n";
    } else {
        const auto constants = [&](std::span<const float> vector) {
            return brdf([vector](int i) { return glslFloat(vector[static_cast<std::size_t>(i)]); });
        };
        s += "            vec3 region = " + constants(map.mean) + ";\n";
        for (int j = 0; j < map.rank; ++j) {
            s += "            region += " + layerComponent("w", j) + " * (" +
                 constants(map.basis.subspan(static_cast<std::size_t>(j * values),
                                             static_cast<std::size_t>(values))) +
                 ");\n";
        }
    }
    s += "            f += alpha * region;\n        }\n";
    return s;
}

// A curve's samples divided by the last (r(1) = 1), as the renderer uploads them.
std::vector<float> normalizedCurve(const std::vector<float>& samples) {
    std::vector<float> curve;
    for (float sample : samples) {
        curve.push_back(sample / samples.back());
    }
    return curve;
}

// GLSL turning `relative` (r wanted per channel) into `level`: compensatePixel's clipping and
// ProjectorResponse::level, for this bundle's response only (a shader that handled both kinds
// behind a uniform paid for both on llvmpipe: ~17% of the low-rank frame).
std::string compensationGlsl(const proto::RenderSettings& settings) {
    if (settings.response.kind != proto::ResponseKind::kCurve) {
        // r(v) = v^γ: black level 0, level = r^(1/γ) on [0, 1]; 1/γ as the CPU takes it.
        std::string inverse;
        for (std::size_t c = 0; c < 3; ++c) {
            inverse +=
                (c == 0 ? "" : ", ") + glslFloat(static_cast<float>(
                                           1.0 / static_cast<double>(settings.response.gamma[c])));
        }
        return "    vec3 level = pow(clamp(relative, 0.0, 1.0), vec3(" + inverse +
               "));\n"
               "    level = mix(level, vec3(1.0), greaterThan(relative, vec3(1.0)));\n"
               "    level = mix(level, vec3(0.0), lessThan(relative, vec3(0.0)));\n";
    }
    // A sampled curve (row c of uCurve, normalized): below its first sample (the black level)
    // 0, above 1 full, else the first sample at or above r and the one before, interpolated.
    std::string s = "    vec3 level;\n";
    for (std::size_t c = 0; c < 3; ++c) {
        const std::vector<float> curve = normalizedCurve(settings.response.curve[c]);
        std::string channel = R"GLSL(    {
        float fraction = relative[@C@];
        float previous = @FIRST@;
        level[@C@] = fraction > 1.0 ? 1.0 : 0.0;
        if (fraction > previous && fraction <= 1.0) {
            level[@C@] = 1.0;
            for (int k = 1; k < @SAMPLES@; ++k) {
                float output_ = texelFetch(uCurve, ivec2(k, @C@), 0).x;
                if (output_ >= fraction) {
                    float f = (fraction - previous) / (output_ - previous);
                    level[@C@] = clamp((float(k - 1) + f) / @STEPS@.0, 0.0, 1.0);
                    break;
                }
                previous = output_;
            }
        }
    }
)GLSL";
        const std::pair<std::string, std::string> values[] = {
            {"@C@", std::to_string(c)},
            {"@FIRST@", glslFloat(curve.front())},
            {"@SAMPLES@", std::to_string(curve.size())},
            {"@STEPS@", std::to_string(curve.size() - 1)}};
        for (const auto& [name, value] : values) {
            for (std::size_t at = channel.find(name); at != std::string::npos;
                 at = channel.find(name, at + value.size())) {
                channel.replace(at, name.size(), value);
            }
        }
        s += channel;
    }
    return s;
}

}  // namespace

std::string shadingShaderSource(const proto::BundleView& bundle) {
    const bool hasWeights = !bundle.presets().empty();
    std::string s = "#version 310 es\n";
    s += kCommonGlsl;
    s += kPixelGlsl;
    s += fourierBrdfGlsl(bundle.model().harmonics);
    s += fourierBasisGlsl(bundle.model().harmonics);
    s += R"GLSL(
uniform highp usampler2D uIds;
uniform highp sampler2D uRays;
uniform highp sampler2DArray uWeights;
uniform highp sampler2D uCurve;     // R32F: row c the normalized response curve of channel c
                                    // (curve responses only)
uniform vec3 uLightPosition;
uniform vec3 uLightIntensity;
uniform bool uInverseSquare;
uniform float uReferenceDistance;
uniform vec3 uViewer;
uniform float uGain;
uniform vec3 uAlbedo;
uniform vec3 uAmbient;
uniform float uPeakIrradiance;
layout(location = 0) out vec4 outLevel;
)GLSL";
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        s += "uniform highp sampler2DArray uRegion" + std::to_string(r) + ";\n";
    }
    s += R"GLSL(

void main() {
    ivec2 pixel = vpePixel();
    uint id = texelFetch(uIds, ivec2(gl_FragCoord.xy), 0).x;
    if (id == 0u) {
        outLevel = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    int triangle = int(id - 1u);
    vec4 t0 = vpeTriangleTexel(triangle, 0), t1 = vpeTriangleTexel(triangle, 1);
    vec4 t2 = vpeTriangleTexel(triangle, 2), t3 = vpeTriangleTexel(triangle, 3);
    vec4 t4 = vpeTriangleTexel(triangle, 4), t5 = vpeTriangleTexel(triangle, 5);
    vec3 p0 = t0.xyz, p1 = t1.xyz, p2 = t2.xyz;
    vec2 ab = texelFetch(uRays, pixel, 0).xy;
    vec3 direction = uRt * vec3(ab, 1.0);
    bool hit;
    vec3 tb = vpeIntersect(uCenter, direction, p0, p1, p2, hit);
    float b1 = clamp(tb.y, 0.0, 1.0);
    float b2 = clamp(tb.z, 0.0, 1.0 - b1);
    float b0 = 1.0 - b1 - b2;
    vec3 position = uCenter + tb.x * direction;

    // renderer::surfacePoint: two-sided shading normal.
    vec3 geometric = cross(p1 - p0, p2 - p0);
    float geometricLength = length(geometric);
    geometric = geometricLength > 0.0 ? geometric / geometricLength : vec3(0.0, 0.0, 1.0);
    vec3 interpolated = b0 * t3.xyz + b1 * t4.xyz + b2 * t5.xyz;
    float interpolatedLength = length(interpolated);
    vec3 normal = interpolatedLength > 0.0 ? interpolated / interpolatedLength : geometric;
    if (dot(geometric, normal) < 0.0) {
        geometric = -geometric;
    }
    if (dot(geometric, direction) > 0.0) {
        geometric = -geometric;
        normal = -normal;
    }
    // The bundle's uvs have rows from the top, as the textures were uploaded: no flip.
    vec2 uv = b0 * vec2(t0.w, t1.w) + b1 * vec2(t2.w, t3.w) + b2 * vec2(t4.w, t5.w);

    vec3 toLight = uLightPosition - position;
    vec3 toViewer = uViewer - position;
    float lightDistance = length(toLight), viewerDistance = length(toViewer);
    vec3 radiance = vec3(0.0);
    if (lightDistance > 0.0 && viewerDistance > 0.0) {
        vec2 angles = vpeReflectionAngles(normal, toLight / lightDistance, toViewer / viewerDistance);
        float basis[VPE_COEFFICIENTS];
        vpeFourierBasis(angles.x, angles.y, basis);
        vec3 f = vec3(0.0);
)GLSL";
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        s += regionBrdfGlsl(bundle, r, hasWeights);
    }
    s += R"GLSL(
        vec3 irradiance = uLightIntensity;
        if (uInverseSquare) {
            irradiance *= uReferenceDistance * uReferenceDistance / dot(toLight, toLight);
        }
        radiance = max(uGain * irradiance * f, vec3(0.0));
    }

    // renderer::projectorIrradianceScale and compensatePixel.
    vec3 toProjector = uCenter - position;
    float distanceSquared = dot(toProjector, toProjector);
    float cosine = dot(normal, toProjector) / sqrt(distanceSquared);
    float scale = cosine > 0.0 ? uPeakIrradiance * cosine / distanceSquared : 0.0;
    vec3 wanted = 3.14159265358979323846 * radiance / uAlbedo - uAmbient;
    // S = 0: ±∞, clipped either way (2 > 1, −2 < every black level), or 0.
    vec3 relative = scale > 0.0 ? wanted / scale : 2.0 * sign(wanted);
)GLSL";
    s += compensationGlsl(bundle.settings());
    s += R"GLSL(
    outLevel = vec4(level, 1.0);
}
)GLSL";
    return s;
}

namespace {

GlObject makeTexture2D(GLenum internalFormat, int width, int height, GLenum format, GLenum type,
                       const void* data) {
    GlObject texture = GlObject::texture();
    glBindTexture(GL_TEXTURE_2D, texture.get());
    glTexStorage2D(GL_TEXTURE_2D, 1, internalFormat, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (data != nullptr) {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format, type, data);
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

// The triangle table: per triangle kTriangleTexels RGBA32F texels, positions and normals of its
// vertices in xyz and their uvs in w (the layout vpeTriangleTexel reads).
GlObject makeTriangleTable(const proto::MeshView& mesh) {
    const std::size_t triangles = mesh.triangleCount();
    const std::size_t rows =
        std::max<std::size_t>(1, (triangles + kTrianglesPerRow - 1) / kTrianglesPerRow);
    const std::size_t width = kTrianglesPerRow * kTriangleTexels;
    std::vector<float> table(rows * width * 4, 0.0f);
    for (std::size_t t = 0; t < triangles; ++t) {
        float* record =
            table.data() +
            ((t / kTrianglesPerRow) * width + (t % kTrianglesPerRow) * kTriangleTexels) * 4;
        for (std::size_t corner = 0; corner < 3; ++corner) {
            const std::size_t v = mesh.indices[3 * t + corner];
            for (std::size_t i = 0; i < 3; ++i) {
                record[4 * corner + i] = mesh.positions[3 * v + i];
                record[4 * (3 + corner) + i] = mesh.normals[3 * v + i];
            }
            // w: u0 v0 u1 v1 u2 v2 over the six texels.
            record[4 * (2 * corner) + 3] = mesh.uvs[2 * v];
            record[4 * (2 * corner + 1) + 3] = mesh.uvs[2 * v + 1];
        }
    }
    return makeTexture2D(GL_RGBA32F, static_cast<int>(width), static_cast<int>(rows), GL_RGBA,
                         GL_FLOAT, table.data());
}

GLint location(unsigned program, const char* name) {
    return glGetUniformLocation(program, name);
}

}  // namespace

GlesFrameRenderer::GlesFrameRenderer(const proto::BundleView& bundle,
                                     const GlesRendererOptions& options)
    : bundleName_(bundle.name()), reuseVisibility_(options.reuseVisibility) {
    const proto::ProjectorCalibration& projector = bundle.projector();
    width_ = static_cast<int>(projector.width);
    height_ = static_cast<int>(projector.height);
    harmonics_ = bundle.model().harmonics;
    GLint maxTexture = 0, maxLayers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    const int maxSize = std::min(maxTexture, options.maxTextureSize);
    if (width_ > maxSize || height_ > maxSize) {
        throw GraphicsError(bundleName_ + ": projector " + std::to_string(width_) + "x" +
                            std::to_string(height_) + " is larger than the texture limit " +
                            std::to_string(maxSize));
    }
    uploadMesh(bundle);
    uploadTextures(bundle, maxSize);
    buildPrograms(bundle);
    vertexArray_ = GlObject::vertexArray();
    checkGlError(bundleName_ + ": uploading the bundle");
    selectPreset("");
}

GlesFrameRenderer::~GlesFrameRenderer() = default;

void GlesFrameRenderer::uploadMesh(const proto::BundleView& bundle) {
    const proto::MeshView& mesh = bundle.mesh();
    triangles_ = mesh.triangleCount();
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    const std::size_t rows = (triangles_ + kTrianglesPerRow - 1) / kTrianglesPerRow;
    if (rows > static_cast<std::size_t>(maxTexture)) {
        throw GraphicsError(bundleName_ + ": the mesh is too large for the renderer (" +
                            std::to_string(mesh.vertexCount()) + " vertices, " +
                            std::to_string(mesh.triangleCount()) + " triangles)");
    }
    triangleTable_ = makeTriangleTable(mesh);

    // The projector: the rays of its pixel centres, undistorted exactly as the CPU does.
    const proto::ProjectorCalibration& calibration = bundle.projector();
    PinholeCamera camera;
    camera.width = width_;
    camera.height = height_;
    camera.K = calibration.intrinsics;
    camera.distortion = calibration.distortion;
    camera.R = calibration.rotation;
    camera.T = calibration.translation;
    std::vector<float> rays(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) *
                            2);
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
            const Vec2d ideal = undistortNormalized(
                camera.distortion,
                pixelToNormalized(camera, {static_cast<double>(x), static_cast<double>(y)}));
            const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                                   static_cast<std::size_t>(x)) *
                                  2;
            rays[i] = static_cast<float>(ideal.x);
            rays[i + 1] = static_cast<float>(ideal.y);
        }
    }
    rays_ = makeTexture2D(GL_RG32F, width_, height_, GL_RG, GL_FLOAT, rays.data());
    for (std::size_t i = 0; i < 9; ++i) {
        rotation_[i] = static_cast<float>(calibration.rotation[i]);
    }
    const Vec3d center = camera.center();
    center_ = {static_cast<float>(center.x), static_cast<float>(center.y),
               static_cast<float>(center.z)};
    for (std::size_t i = 0; i < 3; ++i) {
        translation_[i] = static_cast<float>(calibration.translation[i]);
    }
    intrinsics_ = {static_cast<float>(calibration.intrinsics[0]),
                   static_cast<float>(calibration.intrinsics[4]),
                   static_cast<float>(calibration.intrinsics[2]),
                   static_cast<float>(calibration.intrinsics[5])};
    skew_ = static_cast<float>(calibration.intrinsics[1]);
    for (std::size_t i = 0; i < 5; ++i) {
        distortion_[i] = static_cast<float>(calibration.distortion[i]);
    }
    double farthest = 0;
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        const Vec3d x = camera.toCamera({static_cast<double>(mesh.positions[3 * v]),
                                         static_cast<double>(mesh.positions[3 * v + 1]),
                                         static_cast<double>(mesh.positions[3 * v + 2])});
        farthest = std::max(farthest, x.z);
    }
    depthScale_ = farthest > 0 ? static_cast<float>(1.0 / (1.01 * farthest)) : 1.0f;

    const proto::RenderSettings& settings = bundle.settings();
    albedo_ = settings.screenAlbedo;
    ambient_ = settings.ambientIrradiance;
    peakIrradiance_ = settings.peakIrradiance;
    curveResponse_ = settings.response.kind == proto::ResponseKind::kCurve;
    if (curveResponse_) {
        for (std::size_t c = 0; c < 3; ++c) {
            curve_[c] = normalizedCurve(settings.response.curve[c]);
        }
    }
}

void GlesFrameRenderer::uploadTextures(const proto::BundleView& bundle, int maxSize) {
    const int w = bundle.textureWidth(), h = bundle.textureHeight();
    if (w > maxSize || h > maxSize) {
        throw GraphicsError(bundleName_ + ": textures " + std::to_string(w) + "x" +
                            std::to_string(h) + " are larger than the limit " +
                            std::to_string(maxSize) + " (GL_MAX_TEXTURE_SIZE and 4096)");
    }
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    const std::size_t regions = bundle.regions().size();
    if (static_cast<int>(regions) + kUnitRegions > units) {
        throw GraphicsError(bundleName_ + ": " + std::to_string(regions) +
                            " regions need more texture units than the " + std::to_string(units) +
                            " the GPU has (at most " + std::to_string(units - kUnitRegions) + ")");
    }
    GLint maxLayers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
    // The low-rank means and bases are constants of the shading shader (regionBrdfGlsl).
    for (const proto::RegionView& region : bundle.regions()) {
        const proto::HalfLayers& layers = region.coefficients.layers;
        if (layers.layers > maxLayers) {
            throw GraphicsError(bundleName_ + ": " + std::to_string(layers.layers) +
                                " texture layers exceed GL_MAX_ARRAY_TEXTURE_LAYERS " +
                                std::to_string(maxLayers));
        }
        regionTextures_.push_back(makeArrayTexture(GL_RGBA16F, w, h, layers.layers, GL_RGBA,
                                                   GL_HALF_FLOAT, layers.halves.data()));
    }
    for (const proto::WeightPresetView& preset : bundle.presets()) {
        presetNames_.emplace_back(preset.name);
        if (preset.encoding == proto::AlphaEncoding::kUnorm8) {
            presetTextures_.push_back(makeArrayTexture(GL_R8, w, h, preset.layers, GL_RED,
                                                       GL_UNSIGNED_BYTE, preset.unorm8.data()));
        } else {
            presetTextures_.push_back(makeArrayTexture(GL_R16F, w, h, preset.layers, GL_RED,
                                                       GL_HALF_FLOAT, preset.halves.data()));
        }
    }
    if (presetTextures_.empty() && regions > 1) {
        throw std::invalid_argument(bundleName_ + ": " + std::to_string(regions) +
                                    " regions and no weight preset to blend them");
    }
    if (curveResponse_) {
        std::size_t samples = 0;
        for (const auto& channel : curve_) {
            samples = std::max(samples, channel.size());
        }
        if (samples > static_cast<std::size_t>(maxSize)) {
            throw GraphicsError(bundleName_ + ": the response curve has " +
                                std::to_string(samples) + " samples, more than " +
                                std::to_string(maxSize));
        }
        std::vector<float> table(samples * 3, 0.0f);
        for (std::size_t ch = 0; ch < 3; ++ch) {
            std::copy(curve_[ch].begin(), curve_[ch].end(), table.begin() + ch * samples);
        }
        curveTexture_ =
            makeTexture2D(GL_R32F, static_cast<int>(samples), 3, GL_RED, GL_FLOAT, table.data());
    } else {
        const float zero = 0.0f;
        curveTexture_ = makeTexture2D(GL_R32F, 1, 1, GL_RED, GL_FLOAT, &zero);
    }
}

void GlesFrameRenderer::buildPrograms(const proto::BundleView& bundle) {
    const std::string header = std::string("#version 310 es\n") + kCommonGlsl;
    {
        const unsigned vertex =
            compileShader(GL_VERTEX_SHADER, "visibility.vert", header + kVisibilityVertex);
        unsigned fragment = 0;
        try {
            fragment = compileShader(GL_FRAGMENT_SHADER, "visibility.frag",
                                     header + kPixelGlsl + kVisibilityFragment);
        } catch (...) {
            glDeleteShader(vertex);
            throw;
        }
        visibilityProgram_ = GlObject::program(linkProgram("visibility", vertex, fragment));
    }
    {
        const unsigned vertex =
            compileShader(GL_VERTEX_SHADER, "fullscreen.vert", kFullScreenVertex);
        unsigned fragment = 0;
        try {
            fragment =
                compileShader(GL_FRAGMENT_SHADER, "shading.frag", shadingShaderSource(bundle));
        } catch (...) {
            glDeleteShader(vertex);
            throw;
        }
        shadingProgram_ = GlObject::program(linkProgram("shading", vertex, fragment));
    }
}

void GlesFrameRenderer::selectPreset(const std::string& name) {
    if (presetNames_.empty()) {
        if (!name.empty()) {
            throw std::invalid_argument(bundleName_ + ": no weight preset '" + name +
                                        "' (it has none)");
        }
        presetName_.clear();
        return;
    }
    for (std::size_t i = 0; i < presetNames_.size(); ++i) {
        if (name.empty() || presetNames_[i] == name) {
            preset_ = i;
            presetName_ = presetNames_[i];
            return;
        }
    }
    std::string names;
    for (const std::string& candidate : presetNames_) {
        names += (names.empty() ? "" : ", ") + candidate;
    }
    throw std::invalid_argument(bundleName_ + ": no weight preset '" + name +
                                "' (it has: " + names + ")");
}

void GlesFrameRenderer::ensureVisibilityBuffer() {
    if (idFramebuffer_.get() != 0) {
        return;
    }
    idTexture_ = makeTexture2D(GL_R32UI, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    depthBuffer_ = GlObject::renderbuffer();
    glBindRenderbuffer(GL_RENDERBUFFER, depthBuffer_.get());
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width_, height_);
    idFramebuffer_ = GlObject::framebuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, idFramebuffer_.get());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, idTexture_.get(),
                           0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              depthBuffer_.get());
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        throw GraphicsError(bundleName_ + ": the R32UI + DEPTH32F visibility buffer is incomplete");
    }
}

void GlesFrameRenderer::render(RenderTarget& target, const FrameInputs& inputs,
                               FramePassTimes* passTimes) {
    if (target.width() != width_ || target.height() != height_) {
        throw GraphicsError("render target " + std::to_string(target.width()) + "x" +
                            std::to_string(target.height()) + " is not the projector's " +
                            std::to_string(width_) + "x" + std::to_string(height_));
    }
    if (!(inputs.gain > 0)) {
        throw std::invalid_argument("gain must be positive");
    }
    ensureVisibilityBuffer();
    // Profiling: finish the GPU's work and time it since the previous lap.
    auto lapStart = std::chrono::steady_clock::now();
    const auto lap = [&](double* ms) {
        if (ms == nullptr) {
            return;
        }
        glFinish();
        const auto now = std::chrono::steady_clock::now();
        *ms = std::chrono::duration<double, std::milli>(now - lapStart).count();
        lapStart = now;
    };
    if (passTimes != nullptr) {
        glFinish();
        lapStart = std::chrono::steady_clock::now();
    }
    const bool topRow = target.topRowAtGlOrigin();
    const auto common = [&](unsigned program) {
        glUseProgram(program);
        glUniform1i(location(program, "uTriangles"), kUnitTriangles);
        glUniform2f(location(program, "uSize"), static_cast<float>(width_),
                    static_cast<float>(height_));
        glUniform1i(location(program, "uTopRowAtOrigin"), topRow ? 1 : 0);
        glUniformMatrix3fv(location(program, "uRt"), 1, GL_FALSE, rotation_.data());
        glUniform3fv(location(program, "uT"), 1, translation_.data());
        glUniform3fv(location(program, "uCenter"), 1, center_.data());
        glUniform1i(location(program, "uRays"), kUnitRays);
    };
    const auto bind = [](int unit, GLenum kind, const GlObject& texture) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        glBindTexture(kind, texture.get());
    };
    bind(kUnitTriangles, GL_TEXTURE_2D, triangleTable_);
    bind(kUnitRays, GL_TEXTURE_2D, rays_);
    bind(kUnitCurve, GL_TEXTURE_2D, curveTexture_);
    if (!presetTextures_.empty()) {
        bind(kUnitWeights, GL_TEXTURE_2D_ARRAY, presetTextures_[preset_]);
    }
    for (std::size_t r = 0; r < regionTextures_.size(); ++r) {
        bind(kUnitRegions + static_cast<int>(r), GL_TEXTURE_2D_ARRAY, regionTextures_[r]);
    }
    glBindVertexArray(vertexArray_.get());
    glViewport(0, 0, width_, height_);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);

    // Pass 1: the nearest triangle each pixel's exact ray hits. It depends on the mesh and the
    // projector only, both fixed for the renderer's life: drawn once per orientation.
    const int orientation = topRow ? 1 : 0;
    const bool drawVisibility = !reuseVisibility_ || visibilityOrientation_ != orientation;
    if (passTimes != nullptr) {
        passTimes->visibilityDrawn = drawVisibility;
        passTimes->visibilityMs = 0;
    }
    if (drawVisibility) {
        glBindFramebuffer(GL_FRAMEBUFFER, idFramebuffer_.get());
        const GLuint zero[4] = {0, 0, 0, 0};
        glClearBufferuiv(GL_COLOR, 0, zero);
        glClearDepthf(1.0f);
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        const unsigned visibility = visibilityProgram_.get();
        common(visibility);
        glUniform4fv(location(visibility, "uIntrinsics"), 1, intrinsics_.data());
        glUniform1f(location(visibility, "uSkew"), skew_);
        glUniform1fv(location(visibility, "uDistortion"), 5, distortion_.data());
        glUniform1f(location(visibility, "uMargin"), kCoverMarginPixels);
        glUniform1f(location(visibility, "uDepthScale"), depthScale_);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(6 * triangles_));
        glDisable(GL_DEPTH_TEST);
        // Only the ids are read back: a tile-based GPU (the Pi's V3D) need not store the depths.
        const GLenum depthAttachment = GL_DEPTH_ATTACHMENT;
        glInvalidateFramebuffer(GL_FRAMEBUFFER, 1, &depthAttachment);
        visibilityOrientation_ = orientation;
        lap(passTimes != nullptr ? &passTimes->visibilityMs : nullptr);
    }

    // Pass 2: shading and compensation, once per pixel.
    bind(kUnitIds, GL_TEXTURE_2D, idTexture_);
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    const unsigned shading = shadingProgram_.get();
    common(shading);
    glUniform1i(location(shading, "uIds"), kUnitIds);
    glUniform1i(location(shading, "uWeights"), kUnitWeights);
    glUniform1i(location(shading, "uCurve"), kUnitCurve);
    for (std::size_t r = 0; r < regionTextures_.size(); ++r) {
        glUniform1i(location(shading, ("uRegion" + std::to_string(r)).c_str()),
                    kUnitRegions + static_cast<int>(r));
    }
    glUniform3fv(location(shading, "uLightPosition"), 1, inputs.lightPosition.data());
    glUniform3fv(location(shading, "uLightIntensity"), 1, inputs.lightIntensity.data());
    glUniform1i(location(shading, "uInverseSquare"), inputs.inverseSquare ? 1 : 0);
    glUniform1f(location(shading, "uReferenceDistance"), inputs.referenceDistance);
    glUniform3fv(location(shading, "uViewer"), 1, inputs.viewerPosition.data());
    glUniform1f(location(shading, "uGain"), inputs.gain);
    glUniform3fv(location(shading, "uAlbedo"), 1, albedo_.data());
    glUniform3fv(location(shading, "uAmbient"), 1, ambient_.data());
    glUniform1f(location(shading, "uPeakIrradiance"), peakIrradiance_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    lap(passTimes != nullptr ? &passTimes->shadingMs : nullptr);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError(bundleName_ + ": rendering a frame");
}

}  // namespace vpe::renderer::gles
