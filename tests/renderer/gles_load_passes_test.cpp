// SPDX-License-Identifier: MIT
// What the GLES renderer computes once per bundle, against its C++ definition: the geometry
// buffer as uploaded (every pixel equal, bit for bit, to packProjectorPixel of the CPU
// reference's traced pixel — bands, formats, orientation), the shading geometry pass's packing
// (position about the centre, n, the mirrored viewer, the geometric normal) and the material
// pass's projector-space material (the θs maps sampled bilinearly at the pixel's uv, blended by
// the preset, times the viewer's horizon, as half floats, and the geometric normal's z after
// them). Read back by a compute shader.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <GLES3/gl31.h>
#include <gtest/gtest.h>

#include "vpe/proto/half_float.h"
#include "vpe/proto/surface_horizon.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/renderer/bundle_scene.h"
#include "vpe/renderer/gles/geometry_buffer.h"
#include "vpe/renderer/gles/material_pass.h"
#include "vpe/renderer/gles/shading_geometry_pass.h"
#include "vpe/renderer/gles/shading_glsl.h"
#include "vpe/renderer/gles/theta_textures.h"
#include "vpe/renderer/gles/tile_cover.h"
#include "vpe/renderer/projector_pixels.h"
#include "vpe/renderer/theta_material.h"

#include "gles_test_bundle.h"
#include "gles_test_platform.h"

namespace vpe::renderer::testing {
namespace {

using gles::GlObject;

class GlesLoadPassesTest : public GlesTest {};

// Every texel of a 2D (layer < 0) or 2D-array integer or float texture as 4 words, rows of the
// texture in order, by a compute shader (reading back without a framebuffer).
std::vector<std::uint32_t> readTexels(unsigned texture, int width, int height, const char* type,
                                      int layer = -1) {
    const bool array = layer >= 0;
    std::string source = "#version 310 es\nprecision highp float;\nprecision highp int;\n";
    source += std::string("uniform highp ") + type + " uTexture;\n";
    source += R"GLSL(
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Outputs { uvec4 outputs[]; };
uniform ivec2 uSize;
uniform int uLayer;
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= uSize.x * uSize.y) {
        return;
    }
    ivec2 p = ivec2(i % uSize.x, i / uSize.x);
)GLSL";
    const std::string fetch =
        array ? "texelFetch(uTexture, ivec3(p, uLayer), 0)" : "texelFetch(uTexture, p, 0)";
    source += std::string(type).find("usampler") != std::string::npos
                  ? "    outputs[i] = " + fetch + ";\n}\n"
                  : "    outputs[i] = floatBitsToUint(" + fetch + ");\n}\n";
    const unsigned shader = gles::compileShader(GL_COMPUTE_SHADER, "read.comp", source);
    GlObject program = GlObject::program(gles::linkProgram("read", shader));
    const std::size_t texels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    GlObject out = GlObject::buffer();
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, out.get());
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(texels * 16), nullptr,
                 GL_STATIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.get());
    glUseProgram(program.get());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(array ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D, texture);
    glUniform1i(glGetUniformLocation(program.get(), "uTexture"), 0);
    glUniform2i(glGetUniformLocation(program.get(), "uSize"), width, height);
    glUniform1i(glGetUniformLocation(program.get(), "uLayer"), std::max(layer, 0));
    glDispatchCompute(static_cast<GLuint>((texels + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<std::uint32_t> words(texels * 4);
    const void* mapped = glMapBufferRange(GL_SHADER_STORAGE_BUFFER, 0,
                                          static_cast<GLsizeiptr>(texels * 16), GL_MAP_READ_BIT);
    EXPECT_NE(mapped, nullptr);
    if (mapped != nullptr) {
        std::memcpy(words.data(), mapped, texels * 16);
        glUnmapBuffer(GL_SHADER_STORAGE_BUFFER);
    }
    gles::checkGlError("reading a texture back");
    return words;
}

TEST_F(GlesLoadPassesTest, GeometryBufferHoldsTheCpuReferencesTracedPixels) {
    MappedTestBundle bundle;
    const BundleScene scene(bundle.view(), "");
    const RenderScene any = scene.scene({}, scene.bundleViewer());
    const ProjectorPixels pixels(any.mesh, any.projector);
    const gles::GeometryBuffer geometry(pixels, 2);
    const int w = geometry.width(), h = geometry.height();
    const auto g0 = readTexels(geometry.geometry0().get(), w, h, "sampler2D");
    const auto g1 = readTexels(geometry.geometry1().get(), w, h, "usampler2D");
    const auto uv = readTexels(geometry.uv().get(), w, h, "sampler2D");
    std::size_t covered = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::optional<ProjectorPixel> traced = pixels.trace(x, y);
            covered += traced ? 1 : 0;
            const gles::PackedPixel packed = gles::packProjectorPixel(traced);
            const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                       static_cast<std::size_t>(x));
            for (std::size_t k = 0; k < 4; ++k) {
                ASSERT_EQ(g0[i + k], std::bit_cast<std::uint32_t>(packed.geometry0[k]))
                    << x << "," << y;
                ASSERT_EQ(g1[i + k], packed.geometry1[k]) << x << "," << y;
            }
            ASSERT_EQ(uv[i], std::bit_cast<std::uint32_t>(packed.uv[0])) << x << "," << y;
            ASSERT_EQ(uv[i + 1], std::bit_cast<std::uint32_t>(packed.uv[1])) << x << "," << y;
        }
    }
    EXPECT_EQ(covered, geometry.coveredPixels());
    EXPECT_GT(covered, static_cast<std::size_t>(w * h / 10));
}

// The shading geometry pass against its C++ definition: per covered pixel the position about
// the centre and 1/S (half floats), n, the mirrored viewer (mirroredViewer of the traced normal
// and the direction to the viewer, in double) and the geometric normal, within half-float
// rounding; the geometric normal's z is the material's (tested with the material pass).
TEST_F(GlesLoadPassesTest, ShadingGeometryPacksTheTracedPixels) {
    MappedTestBundle bundle;
    const BundleScene scene(bundle.view(), "");
    const RenderScene any = scene.scene({}, scene.bundleViewer());
    const ProjectorPixels pixels(any.mesh, any.projector);
    const gles::GeometryBuffer geometry(pixels, 2);
    const gles::TileCover tiles(geometry.width(), geometry.height(), geometry.coveredTiles());
    const Vec3d eye = scene.bundleViewer();
    const std::array<float, 3> viewer{static_cast<float>(eye.x), static_cast<float>(eye.y),
                                      static_cast<float>(eye.z)};
    gles::ShadingGeometryPass pass(geometry, tiles, viewer);
    pass.run();
    const int w = geometry.width(), h = geometry.height();
    const auto shading = readTexels(pass.shading().get(), w, h, "usampler2D");
    const auto position = readTexels(pass.position().get(), w, h, "sampler2D");
    const std::array<double, 3>& centre = geometry.centre();
    double worstPosition = 0, worstVector = 0;
    std::size_t checked = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::optional<ProjectorPixel> traced = pixels.trace(x, y);
            if (!traced) {
                continue;
            }
            const gles::PackedPixel packed = gles::packProjectorPixel(traced);
            const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                       static_cast<std::size_t>(x));
            const Vec3d& X = traced->point.position;
            const std::array<double, 3> stored{X.x, X.y, X.z};
            for (std::size_t k = 0; k < 3; ++k) {
                const double expected = stored[k] - centre[k];
                worstPosition =
                    std::max(worstPosition,
                             std::fabs(static_cast<double>(std::bit_cast<float>(position[i + k])) -
                                       expected) /
                                 std::max(std::fabs(expected), 1e-3));
            }
            ASSERT_NEAR(std::bit_cast<float>(position[i + 3]),
                        std::min(packed.geometry0[3], 65504.0f),
                        std::fabs(packed.geometry0[3]) * 1e-3f)
                << x << "," << y;
            const Vec3d& n = traced->point.normal;
            const Vec3d toViewer = proto::normalized(Vec3d{static_cast<double>(viewer[0]) - X.x,
                                                           static_cast<double>(viewer[1]) - X.y,
                                                           static_cast<double>(viewer[2]) - X.z});
            const Vec3d m = gles::mirroredViewer(n, toViewer);
            const Vec3d g = gles::decodeOctahedralNormal(packed.geometry1[3]);
            const auto half = [&](std::size_t word, int high) {
                const auto bits = static_cast<std::uint16_t>(shading[i + word] >> (16 * high));
                return static_cast<double>(proto::halfToFloat(bits));
            };
            const std::array<double, 8> expected{n.x, n.y, n.z, m.x, m.y, m.z, g.x, g.y};
            for (std::size_t k = 0; k < 8; ++k) {
                worstVector = std::max(
                    worstVector, std::fabs(half(k / 2, static_cast<int>(k % 2)) - expected[k]));
            }
            ++checked;
        }
    }
    std::cout << "shading geometry: " << checked << " pixels, position within " << worstPosition
              << " of its distance to the centre, n, m, g within " << worstVector << "\n";
    EXPECT_GT(checked, static_cast<std::size_t>(w * h / 10));
    // Half floats: 2⁻¹¹ relative rounded to nearest, 2⁻¹⁰ truncated (llvmpipe writes an RGBA16F
    // target truncating: measured 9.7e-4).
    EXPECT_LT(worstPosition, 1.1e-3);
    EXPECT_LT(worstVector, 5e-4);  // half floats of unit vectors: ≤ 2⁻¹² each, and float m
}

// Bilinear, clamp to edge, texel centres at (i + ½)/size: GL_LINEAR on a texture uploaded rows
// from the top, at a uv in the bundle's convention (rows from the top).
double bilinear(const std::vector<float>& texels, int width, int height, int stride, int value,
                double u, double v) {
    const double s = u * width - 0.5, t = v * height - 0.5;
    const double fs = std::floor(s), ft = std::floor(t);
    const auto at = [&](double x, double y) {
        const int xi = std::clamp(static_cast<int>(x), 0, width - 1);
        const int yi = std::clamp(static_cast<int>(y), 0, height - 1);
        return static_cast<double>(
            texels[static_cast<std::size_t>((yi * width + xi) * stride + value)]);
    };
    const double a = s - fs, b = t - ft;
    return (1 - b) * ((1 - a) * at(fs, ft) + a * at(fs + 1, ft)) +
           b * ((1 - a) * at(fs, ft + 1) + a * at(fs + 1, ft + 1));
}

TEST_F(GlesLoadPassesTest, MaterialPassSamplesBlendsAndPacksAsItsDefinition) {
    MappedTestBundle bundle;
    const proto::BundleView& view = bundle.view();
    const BundleScene scene(view, "");
    const RenderScene any = scene.scene({}, scene.bundleViewer());
    const ProjectorPixels pixels(any.mesh, any.projector);
    const gles::GeometryBuffer geometry(pixels, 2);
    const proto::ThetaBasis basis = proto::ThetaBasis::full(view.model().harmonics);
    const gles::ThetaTextures textures(view, basis, 256, 4096);
    const gles::TileCover tiles(geometry.width(), geometry.height(), geometry.coveredTiles());
    const std::array<float, 3> viewer = view.settings().viewerPosition;
    gles::MaterialPass pass(textures, geometry, tiles, viewer);
    const GlObject target = pass.makeTarget();
    const std::size_t preset = 1;  // "radial": half-float weights
    pass.composePreset(target, preset);

    const int w = geometry.width(), h = geometry.height();
    const int values = textures.layout().materialValues();
    std::vector<std::vector<std::uint32_t>> layers;
    for (int l = 0; l < textures.layout().materialLayers(); ++l) {
        layers.push_back(readTexels(target.get(), w, h, "usampler2DArray", l));
    }
    std::vector<std::vector<float>> maps;
    for (const proto::RegionView& region : view.regions()) {
        maps.push_back(thetaMaterialMap(region.coefficients, basis));
    }
    const proto::WeightPresetView& weights = view.presets()[preset];
    const int tw = view.textureWidth(), th = view.textureHeight();
    const std::size_t texels = static_cast<std::size_t>(tw) * static_cast<std::size_t>(th);
    std::vector<float> alpha(texels * maps.size());  // texel-major, one per region
    for (std::size_t r = 0; r < maps.size(); ++r) {
        for (std::size_t t = 0; t < texels; ++t) {
            alpha[t * maps.size() + r] = proto::halfToFloat(weights.halves[r * texels + t]);
        }
    }
    double worst = 0, largest = 0, worstSpare = 0;
    std::size_t compared = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::optional<ProjectorPixel> traced = pixels.trace(x, y);
            if (!traced) {
                continue;
            }
            const gles::PackedPixel packed = gles::packProjectorPixel(traced);
            const double u = packed.uv[0], v = packed.uv[1];
            const Vec3d position{packed.geometry0[0], packed.geometry0[1], packed.geometry0[2]};
            const Vec3d toViewer =
                proto::normalized(Vec3d{static_cast<double>(viewer[0]) - position.x,
                                        static_cast<double>(viewer[1]) - position.y,
                                        static_cast<double>(viewer[2]) - position.z});
            const Vec3d normal{std::bit_cast<float>(packed.geometry1[0]),
                               std::bit_cast<float>(packed.geometry1[1]),
                               std::bit_cast<float>(packed.geometry1[2])};
            const double horizon = proto::horizonFactor(std::min(
                proto::dot(normal, toViewer),
                proto::dot(gles::decodeOctahedralNormal(packed.geometry1[3]), toViewer)));
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(x);
            for (int q = 0; q < values; ++q) {
                double expected = 0;
                for (std::size_t r = 0; r < maps.size(); ++r) {
                    expected += bilinear(alpha, tw, th, static_cast<int>(maps.size()),
                                         static_cast<int>(r), u, v) *
                                bilinear(maps[r], tw, th, values, q, u, v);
                }
                expected *= horizon;
                const std::uint32_t word =
                    layers[static_cast<std::size_t>(q / 8)][4 * i + (q % 8) / 2];
                const float got = proto::halfToFloat(
                    static_cast<std::uint16_t>(q % 2 == 0 ? word & 0xffffu : word >> 16));
                worst = std::max(worst, std::fabs(static_cast<double>(got) - expected));
                largest = std::max(largest, std::fabs(expected));
                ++compared;
            }
            // The spare half after the values: the geometric normal's z (shading geometry).
            const std::uint32_t spareWord =
                layers[static_cast<std::size_t>(values / 8)][4 * i + (values % 8) / 2];
            const float spare = proto::halfToFloat(static_cast<std::uint16_t>(
                values % 2 == 0 ? spareWord & 0xffffu : spareWord >> 16));
            worstSpare = std::max(worstSpare,
                                  std::fabs(static_cast<double>(spare) -
                                            gles::decodeOctahedralNormal(packed.geometry1[3]).z));
        }
    }
    std::cout << "geometric normal's z in the spare half: within " << worstSpare << "\n";
    EXPECT_LT(worstSpare, 5e-4);  // a half float of a unit vector's component (truncated)
    std::cout << compared << " material values compared: largest |GPU − C++| " << worst
              << " (values up to " << largest << ")\n";
    // Half floats twice (the θs maps and the packed result: 2⁻¹¹ relative each) and the
    // filtering's weights: measured 7.0e-4 of the largest value.
    EXPECT_GT(compared, 10000u);
    EXPECT_LT(worst, 1e-3 * largest);
}

}  // namespace
}  // namespace vpe::renderer::testing
