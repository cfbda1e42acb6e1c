// SPDX-License-Identifier: MIT
// GlesFrameRenderer: upload, shader generation and the two passes (see the header).
#include "vpe/renderer/gles/gles_frame_renderer.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/fourier_brdf_glsl.h"
#include "vpe/renderer/pinhole_camera.h"

namespace vpe::renderer::gles {

namespace {

// Mesh arrays live in 2D textures of this width, read with texelFetch.
constexpr int kRowTexels = 1024;
// Texture units.
constexpr int kUnitIds = 0, kUnitPositions = 1, kUnitNormals = 2, kUnitUvs = 3, kUnitIndices = 4,
              kUnitRays = 5, kUnitWeights = 6, kUnitCurve = 8, kUnitRegions = 9;
// The uniform-buffer binding of the low-rank codes.
constexpr GLuint kLowRankBlockBinding = 0;
// Pixels added around each triangle's box: covers the pixel's own extent, the bend of the
// distorted edges between the sampled points, and float rounding.
constexpr float kBoxMarginPixels = 2.0f;

const char* const kCommonGlsl = R"GLSL(
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp usampler2D;
precision highp sampler2DArray;

uniform highp usampler2D uIndices;  // RGBA32UI: i0, i1, i2 of a triangle
uniform highp sampler2D uPositions; // RGBA32F: xyz
uniform vec2 uSize;                 // projector width, height
uniform bool uTopRowAtOrigin;       // GL row 0 is the projector's top row
uniform mat3 uRt;                   // Rᵀ (R uploaded row-major without transposing)
uniform vec3 uT;                    // T
uniform vec3 uCenter;               // −Rᵀ·T

ivec2 vpeRowTexel(int i) { return ivec2(i % 1024, i / 1024); }
uvec3 vpeTriangle(int t) { return texelFetch(uIndices, vpeRowTexel(t), 0).xyz; }
vec3 vpePosition(uint v) { return texelFetch(uPositions, vpeRowTexel(int(v)), 0).xyz; }


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

void main() {
    int triangle = gl_VertexID / 6;
    int corner = gl_VertexID % 6;
    uvec3 index = vpeTriangle(triangle);
    vec3 p[3] = vec3[3](vpePosition(index.x), vpePosition(index.y), vpePosition(index.z));
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    bool behind = false;
    // The vertices and three points along each edge: a straight edge bends under distortion.
    for (int e = 0; e < 3; ++e) {
        for (int k = 0; k < 4; ++k) {
            vec3 point = mix(p[e], p[(e + 1) % 3], float(k) * 0.25);
            vec3 x = point * uRt + uT;  // R·X + T
            if (x.z <= 1e-6) {
                behind = true;
            } else {
                vec2 pixel = vpeProjectPixel(x);
                lo = min(lo, pixel);
                hi = max(hi, pixel);
            }
        }
    }
    if (behind) {  // crosses the projector's plane: let every pixel test its ray
        lo = vec2(-1.0);
        hi = uSize;
    }
    lo = max(lo - uMargin, vec2(-2.0));
    hi = min(hi + uMargin, uSize + 1.0);
    vec2 pixel = vec2((corner == 1 || corner == 4 || corner == 5) ? hi.x : lo.x,
                      (corner == 2 || corner == 3 || corner == 5) ? hi.y : lo.y);
    // Pixel centres at integers; GL window coordinates put them at + 0.5.
    vec2 window = vec2(pixel.x + 0.5, uTopRowAtOrigin ? pixel.y + 0.5 : uSize.y - 0.5 - pixel.y);
    gl_Position = vec4(window / uSize * 2.0 - 1.0, 0.0, 1.0);
    vTriangle = uint(triangle);
}
)GLSL";

const char* const kVisibilityFragment = R"GLSL(
uniform highp sampler2D uRays;  // RG32F: undistorted (a, b) of each pixel centre, row 0 top
uniform float uDepthScale;
flat in highp uint vTriangle;
layout(location = 0) out highp uint outTriangle;

void main() {
    ivec2 pixel = vpePixel();
    vec2 ab = texelFetch(uRays, pixel, 0).xy;
    vec3 direction = uRt * vec3(ab, 1.0);
    uvec3 index = vpeTriangle(int(vTriangle));
    bool hit;
    vec3 tb = vpeIntersect(uCenter, direction, vpePosition(index.x), vpePosition(index.y),
                           vpePosition(index.z), hit);
    if (!hit) {
        discard;
    }
    gl_FragDepth = clamp(tb.x * uDepthScale, 0.0, 1.0);
    outTriangle = vTriangle + 1u;
}
)GLSL";

const char* const kFullScreenVertex = R"GLSL(#version 310 es
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";

// Rows of the low-rank code block: per low-rank region, μ and its R basis vectors.
int lowRankRows(const proto::BundleView& bundle) {
    int rows = 0;
    for (const proto::RegionView& region : bundle.regions()) {
        if (region.coefficients.encoding == proto::CoefficientEncoding::kLowRank) {
            rows += 1 + region.coefficients.rank;
        }
    }
    return rows;
}

std::string shadingFragment(const proto::BundleView& bundle, bool hasWeights, bool curve) {
    const int c = bundle.model().coefficientsPerTexel();
    const int groups = (c + 3) / 4;
    std::string s = "#version 310 es\n";
    s += kCommonGlsl;
    s += kPixelGlsl;
    s += fourierBrdfGlsl(bundle.model().harmonics);
    s += "#define VPE_GROUPS " + std::to_string(groups) + "\n";
    s += "#define VPE_LOW_RANK_VECTORS " +
         std::to_string(std::max(1, lowRankRows(bundle) * groups)) + "\n";
    s += R"GLSL(
uniform highp usampler2D uIds;
uniform highp sampler2D uRays;
uniform highp sampler2D uNormals;
uniform highp sampler2D uUvs;
uniform highp sampler2DArray uWeights;
// Per low-rank region, row 0 μ, rows 1… B_r, VPE_GROUPS vectors a row: constants, so a uniform
// block (on llvmpipe this measured no faster than an RGBA32F texture: 2057 vs 2148 ms/frame
// at 1080p; the low-rank path's cost lies elsewhere, see README).
layout(std140) uniform VpeLowRankCodes { highp vec4 uLowRank[VPE_LOW_RANK_VECTORS]; };
uniform highp sampler2D uCurve;     // R32F: row c the normalized response curve of channel c
uniform int uCurveCount[3];
uniform vec3 uLightPosition;
uniform vec3 uLightIntensity;
uniform bool uInverseSquare;
uniform float uReferenceDistance;
uniform vec3 uViewer;
uniform float uGain;
uniform vec3 uAlbedo;
uniform vec3 uAmbient;
uniform vec3 uGamma;
uniform bool uCurveResponse;
uniform float uPeakIrradiance;
layout(location = 0) out vec4 outLevel;
)GLSL";
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        s += "uniform highp sampler2DArray uRegion" + std::to_string(r) + ";\n";
    }
    s += R"GLSL(
vec3 vpeNormal(uint v) { return texelFetch(uNormals, vpeRowTexel(int(v)), 0).xyz; }
vec2 vpeUv(uint v) { return texelFetch(uUvs, vpeRowTexel(int(v)), 0).xy; }

// renderer::ProjectorResponse::level for a fraction in [black level, 1].
float vpeLevel(int channel, float fraction) {
    if (!uCurveResponse) {
        return pow(clamp(fraction, 0.0, 1.0), 1.0 / uGamma[channel]);
    }
    int n = uCurveCount[channel];
    float first = texelFetch(uCurve, ivec2(0, channel), 0).x;
    if (fraction <= first) {
        return 0.0;
    }
    float target = min(fraction, 1.0);
    float previous = first;
    for (int k = 1; k < n; ++k) {
        float output_ = texelFetch(uCurve, ivec2(k, channel), 0).x;
        if (output_ >= target) {
            float f = (target - previous) / (output_ - previous);
            float step_ = 1.0 / float(n - 1);
            return clamp(float(k - 1) * step_ + f * step_, 0.0, 1.0);
        }
        previous = output_;
    }
    return 1.0;
}

float vpeBlackLevel(int channel) {
    return uCurveResponse ? texelFetch(uCurve, ivec2(0, channel), 0).x : 0.0;
}

void main() {
    ivec2 pixel = vpePixel();
    uint id = texelFetch(uIds, ivec2(gl_FragCoord.xy), 0).x;
    if (id == 0u) {
        outLevel = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    uvec3 index = vpeTriangle(int(id - 1u));
    vec3 p0 = vpePosition(index.x), p1 = vpePosition(index.y), p2 = vpePosition(index.z);
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
    vec3 interpolated = b0 * vpeNormal(index.x) + b1 * vpeNormal(index.y) + b2 * vpeNormal(index.z);
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
    vec2 uv = b0 * vpeUv(index.x) + b1 * vpeUv(index.y) + b2 * vpeUv(index.z);

    vec3 toLight = uLightPosition - position;
    vec3 toViewer = uViewer - position;
    float lightDistance = length(toLight), viewerDistance = length(toViewer);
    vec3 radiance = vec3(0.0);
    if (lightDistance > 0.0 && viewerDistance > 0.0) {
        vec4 blended[VPE_GROUPS];
        for (int g = 0; g < VPE_GROUPS; ++g) {
            blended[g] = vec4(0.0);
        }
)GLSL";
    int lowRankRow = 0;
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        const proto::CoefficientMapView& map = bundle.regions()[r].coefficients;
        const std::string n = std::to_string(r);
        s += "        {\n";
        s += hasWeights ? "            float w = texture(uWeights, vec3(uv, " + n + ".0)).r;\n"
                        : "            float w = 1.0;\n";
        if (map.encoding == proto::CoefficientEncoding::kFull) {
            s += "            for (int g = 0; g < VPE_GROUPS; ++g) {\n"
                 "                blended[g] += w * texture(uRegion" +
                 n +
                 ", vec3(uv, float(g)));\n"
                 "            }\n";
        } else {
            const int rank = map.rank;
            const int layers = (rank + 3) / 4;
            s += "            float code[" + std::to_string(layers * 4) + "];\n";
            s += "            for (int l = 0; l < " + std::to_string(layers) +
                 "; ++l) {\n"
                 "                vec4 t = texture(uRegion" +
                 n +
                 ", vec3(uv, float(l)));\n"
                 "                code[4 * l] = t.x; code[4 * l + 1] = t.y;\n"
                 "                code[4 * l + 2] = t.z; code[4 * l + 3] = t.w;\n"
                 "            }\n";
            s += "            for (int g = 0; g < VPE_GROUPS; ++g) {\n"
                 "                vec4 value = uLowRank[" +
                 std::to_string(lowRankRow) +
                 " * VPE_GROUPS + g];\n"
                 "                for (int k = 0; k < " +
                 std::to_string(rank) +
                 "; ++k) {\n"
                 "                    value += code[k] * uLowRank[(" +
                 std::to_string(lowRankRow + 1) +
                 " + k) * VPE_GROUPS + g];\n"
                 "                }\n"
                 "                blended[g] += w * value;\n"
                 "            }\n";
            lowRankRow += 1 + rank;
        }
        s += "        }\n";
    }
    s += R"GLSL(
        vec3 coefficients[VPE_COEFFICIENTS];
        for (int k = 0; k < VPE_COEFFICIENTS; ++k) {
            int i = 3 * k;
            coefficients[k] = vec3(blended[i / 4][i % 4], blended[(i + 1) / 4][(i + 1) % 4],
                                   blended[(i + 2) / 4][(i + 2) % 4]);
        }
        vec2 angles = vpeReflectionAngles(normal, toLight / lightDistance, toViewer / viewerDistance);
        vec3 f = vpeFourierBrdf(coefficients, angles.x, angles.y);
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
    vec3 level;
    for (int c = 0; c < 3; ++c) {
        float wanted = 3.14159265358979323846 * radiance[c] / uAlbedo[c] - uAmbient[c];
        float relative = 0.0;
        if (scale > 0.0) {
            relative = wanted / scale;
        } else if (wanted != 0.0) {
            relative = wanted > 0.0 ? 2.0 : -1.0;  // ±∞: clips either way
        }
        if (relative > 1.0) {
            level[c] = 1.0;
        } else if (relative < vpeBlackLevel(c)) {
            level[c] = 0.0;
        } else {
            level[c] = vpeLevel(c, relative);
        }
    }
    outLevel = vec4(level, 1.0);
}
)GLSL";
    (void)curve;
    return s;
}

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

// Per-item data of `components` values each, padded to 4 components, in rows of kRowTexels.
template <typename T>
GlObject makeRowTexture(GLenum internalFormat, GLenum format, GLenum type,
                        std::span<const T> values, int components, std::size_t items) {
    const std::size_t rows = std::max<std::size_t>(1, (items + kRowTexels - 1) / kRowTexels);
    std::vector<T> padded(rows * kRowTexels * 4, T{});
    for (std::size_t i = 0; i < items; ++i) {
        for (int k = 0; k < components; ++k) {
            padded[4 * i + static_cast<std::size_t>(k)] =
                values[i * static_cast<std::size_t>(components) + static_cast<std::size_t>(k)];
        }
    }
    return makeTexture2D(internalFormat, kRowTexels, static_cast<int>(rows), format, type,
                         padded.data());
}

GLint location(unsigned program, const char* name) {
    return glGetUniformLocation(program, name);
}

}  // namespace

GlesFrameRenderer::GlesFrameRenderer(const proto::BundleView& bundle,
                                     const GlesRendererOptions& options)
    : bundleName_(bundle.name()) {
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
    const std::size_t rows =
        (std::max(mesh.vertexCount(), mesh.triangleCount()) + kRowTexels - 1) / kRowTexels;
    if (rows > static_cast<std::size_t>(maxTexture)) {
        throw GraphicsError(bundleName_ + ": the mesh is too large for the renderer (" +
                            std::to_string(mesh.vertexCount()) + " vertices, " +
                            std::to_string(mesh.triangleCount()) + " triangles)");
    }
    positions_ =
        makeRowTexture(GL_RGBA32F, GL_RGBA, GL_FLOAT, mesh.positions, 3, mesh.vertexCount());
    normals_ = makeRowTexture(GL_RGBA32F, GL_RGBA, GL_FLOAT, mesh.normals, 3, mesh.vertexCount());
    uvs_ = makeRowTexture(GL_RGBA32F, GL_RGBA, GL_FLOAT, mesh.uvs, 2, mesh.vertexCount());
    indices_ = makeRowTexture(GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT, mesh.indices, 3,
                              mesh.triangleCount());

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
    gamma_ = settings.response.gamma;
    if (curveResponse_) {
        for (std::size_t c = 0; c < 3; ++c) {
            const std::vector<float>& samples = settings.response.curve[c];
            const float top = samples.back();
            for (float sample : samples) {
                curve_[c].push_back(sample / top);
            }
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
    const int c = bundle.model().coefficientsPerTexel();
    const int groups = (c + 3) / 4;
    std::vector<float> lowRank;  // RGBA32F rows of `groups` texels
    for (const proto::RegionView& region : bundle.regions()) {
        const proto::HalfLayers& layers = region.coefficients.layers;
        if (layers.layers > maxLayers) {
            throw GraphicsError(bundleName_ + ": " + std::to_string(layers.layers) +
                                " texture layers exceed GL_MAX_ARRAY_TEXTURE_LAYERS " +
                                std::to_string(maxLayers));
        }
        regionTextures_.push_back(makeArrayTexture(GL_RGBA16F, w, h, layers.layers, GL_RGBA,
                                                   GL_HALF_FLOAT, layers.halves.data()));
        if (region.coefficients.encoding == proto::CoefficientEncoding::kLowRank) {
            const auto cc = static_cast<std::size_t>(c);
            const auto appendRow = [&](std::span<const float> values) {
                for (int i = 0; i < groups * 4; ++i) {
                    lowRank.push_back(i < c ? values[static_cast<std::size_t>(i)] : 0.0f);
                }
            };
            appendRow(region.coefficients.mean);
            for (int r = 0; r < region.coefficients.rank; ++r) {
                appendRow(region.coefficients.basis.subspan(static_cast<std::size_t>(r) * cc, cc));
            }
        }
    }
    if (lowRank.empty()) {
        lowRank.assign(4, 0.0f);
    }
    GLint maxBlock = 0;
    glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &maxBlock);
    const std::size_t blockBytes = lowRank.size() * sizeof(float);
    if (blockBytes > static_cast<std::size_t>(maxBlock)) {
        throw GraphicsError(
            bundleName_ + ": the low-rank bases need " + std::to_string(blockBytes) +
            " bytes of uniforms, more than GL_MAX_UNIFORM_BLOCK_SIZE " + std::to_string(maxBlock));
    }
    lowRankBuffer_ = GlObject::buffer();
    glBindBuffer(GL_UNIFORM_BUFFER, lowRankBuffer_.get());
    glBufferData(GL_UNIFORM_BUFFER, static_cast<GLsizeiptr>(blockBytes), lowRank.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
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
                compileShader(GL_FRAGMENT_SHADER, "shading.frag",
                              shadingFragment(bundle, !presetTextures_.empty(), curveResponse_));
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

void GlesFrameRenderer::render(RenderTarget& target, const FrameInputs& inputs) {
    if (target.width() != width_ || target.height() != height_) {
        throw GraphicsError("render target " + std::to_string(target.width()) + "x" +
                            std::to_string(target.height()) + " is not the projector's " +
                            std::to_string(width_) + "x" + std::to_string(height_));
    }
    if (!(inputs.gain > 0)) {
        throw std::invalid_argument("gain must be positive");
    }
    ensureVisibilityBuffer();
    const bool topRow = target.topRowAtGlOrigin();
    const auto common = [&](unsigned program) {
        glUseProgram(program);
        glUniform1i(location(program, "uIndices"), kUnitIndices);
        glUniform1i(location(program, "uPositions"), kUnitPositions);
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
    bind(kUnitPositions, GL_TEXTURE_2D, positions_);
    bind(kUnitNormals, GL_TEXTURE_2D, normals_);
    bind(kUnitUvs, GL_TEXTURE_2D, uvs_);
    bind(kUnitIndices, GL_TEXTURE_2D, indices_);
    bind(kUnitRays, GL_TEXTURE_2D, rays_);
    glBindBufferBase(GL_UNIFORM_BUFFER, kLowRankBlockBinding, lowRankBuffer_.get());
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

    // Pass 1: the nearest triangle each pixel's exact ray hits.
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
    glUniform1f(location(visibility, "uMargin"), kBoxMarginPixels);
    glUniform1f(location(visibility, "uDepthScale"), depthScale_);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(6 * triangles_));
    glDisable(GL_DEPTH_TEST);

    // Pass 2: shading and compensation, once per pixel.
    bind(kUnitIds, GL_TEXTURE_2D, idTexture_);
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    const unsigned shading = shadingProgram_.get();
    common(shading);
    glUniform1i(location(shading, "uIds"), kUnitIds);
    glUniform1i(location(shading, "uNormals"), kUnitNormals);
    glUniform1i(location(shading, "uUvs"), kUnitUvs);
    glUniform1i(location(shading, "uWeights"), kUnitWeights);
    // Absent when no region is low-rank (the compiler drops an unused block).
    if (const GLuint block = glGetUniformBlockIndex(shading, "VpeLowRankCodes");
        block != GL_INVALID_INDEX) {
        glUniformBlockBinding(shading, block, kLowRankBlockBinding);
    }
    glUniform1i(location(shading, "uCurve"), kUnitCurve);
    for (std::size_t r = 0; r < regionTextures_.size(); ++r) {
        glUniform1i(location(shading, ("uRegion" + std::to_string(r)).c_str()),
                    kUnitRegions + static_cast<int>(r));
    }
    const GLint counts[3] = {static_cast<GLint>(curve_[0].size()),
                             static_cast<GLint>(curve_[1].size()),
                             static_cast<GLint>(curve_[2].size())};
    glUniform1iv(location(shading, "uCurveCount"), 3, counts);
    glUniform3fv(location(shading, "uLightPosition"), 1, inputs.lightPosition.data());
    glUniform3fv(location(shading, "uLightIntensity"), 1, inputs.lightIntensity.data());
    glUniform1i(location(shading, "uInverseSquare"), inputs.inverseSquare ? 1 : 0);
    glUniform1f(location(shading, "uReferenceDistance"), inputs.referenceDistance);
    glUniform3fv(location(shading, "uViewer"), 1, inputs.viewerPosition.data());
    glUniform1f(location(shading, "uGain"), inputs.gain);
    glUniform3fv(location(shading, "uAlbedo"), 1, albedo_.data());
    glUniform3fv(location(shading, "uAmbient"), 1, ambient_.data());
    glUniform3fv(location(shading, "uGamma"), 1, gamma_.data());
    glUniform1i(location(shading, "uCurveResponse"), curveResponse_ ? 1 : 0);
    glUniform1f(location(shading, "uPeakIrradiance"), peakIrradiance_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError(bundleName_ + ": rendering a frame");
}

}  // namespace vpe::renderer::gles
