// SPDX-License-Identifier: MIT
// What the GLES renderer computes once per bundle, against its C++ definition: the geometry
// buffer as uploaded (every pixel equal, bit for bit, to packProjectorPixel of the CPU
// reference's traced pixel — bands, formats, orientation), the shading geometry pass's packing
// (the position in the object's cube, n, the mirrored viewer, the geometric normal), the
// material pass's projector-space material (the θs maps sampled bilinearly at the pixel's uv,
// blended by the preset, times the viewer's horizon, coded as material_codes.h says, with 1/S
// and the geometric normal's z after the codes) and its blend of coded regions (live weights).
// Read back by a compute shader.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include <GLES3/gl31.h>
#include <gtest/gtest.h>

#include "vpe/proto/half_float.h"
#include "vpe/proto/surface_horizon.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/proto/viewing_zone.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_pixels.h"
#include "vpe/renderer/cpu/theta_material.h"

#include "geometry_buffer.h"
#include "gles_test_bundle.h"
#include "gles_test_platform.h"
#include "material_codes.h"
#include "material_pass.h"
#include "shading_geometry_pass.h"
#include "shading_glsl.h"
#include "theta_textures.h"
#include "tile_cover.h"
#include "weight_pass.h"

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
    const std::string kind(type);
    source += kind.find("usampler") != std::string::npos ? "    outputs[i] = " + fetch + ";\n}\n"
              : kind.find("isampler") != std::string::npos
                  ? "    outputs[i] = uvec4(" + fetch + ");\n}\n"
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

// The test bundle's vase traced from its projector (any light) into a geometry buffer.
struct TracedVase {
    MappedTestBundle bundle;
    BundleScene scene{bundle.view(), ""};
    RenderScene any = scene.scene({}, scene.bundleViewer());
    ProjectorPixels pixels{any.mesh, any.projector};
    gles::GeometryBuffer geometry{pixels, 2};
};

TEST_F(GlesLoadPassesTest, GeometryBufferHoldsTheCpuReferencesTracedPixels) {
    const TracedVase vase;
    const gles::GeometryBuffer& geometry = vase.geometry;
    const int w = geometry.width(), h = geometry.height();
    const auto g0 = readTexels(geometry.geometry0().get(), w, h, "sampler2D");
    const auto g1 = readTexels(geometry.geometry1().get(), w, h, "usampler2D");
    const auto uv = readTexels(geometry.uv().get(), w, h, "sampler2D");
    std::size_t covered = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::optional<ProjectorPixel> traced = vase.pixels.trace(x, y);
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

// The shading geometry pass against its C++ definition: per covered pixel the position as the
// nearest 10-bit fraction of the cube (alpha 1; 0 off the object), n, the mirrored viewer
// (mirroredViewer of the traced normal and the direction to the viewer, in double) and the
// geometric normal's x, y, within half-float rounding; 1/S and the geometric normal's z are the
// material's (tested with the material pass).
void checkShadingGeometry(const TracedVase& vase, const gles::ViewerEyes& eyes);

// For one viewer, and for a viewing zone (proto::zoneEye of the stored geometric normal: 8 eyes
// around the vase, the viewer where none sees a point).
TEST_F(GlesLoadPassesTest, ShadingGeometryPacksTheTracedPixels) {
    const TracedVase vase;
    const Vec3d eye = vase.scene.bundleViewer();
    gles::ViewerEyes one;
    one.viewer = {static_cast<float>(eye.x), static_cast<float>(eye.y), static_cast<float>(eye.z)};
    gles::ViewerEyes zone = one;
    for (int k = 0; k < 8; ++k) {
        const double azimuth = 2 * 3.14159265358979 * k / 8;
        zone.zone.push_back(
            {static_cast<float>(std::sin(azimuth)), 0.075f, static_cast<float>(std::cos(azimuth))});
    }
    for (const gles::ViewerEyes* eyes : {&one, &zone}) {
        SCOPED_TRACE(eyes->zone.empty() ? "one viewer" : "a viewing zone");
        checkShadingGeometry(vase, *eyes);
    }
}

void checkShadingGeometry(const TracedVase& vase, const gles::ViewerEyes& eyes) {
    const gles::GeometryBuffer& geometry = vase.geometry;
    const gles::TileCover tiles(geometry.width(), geometry.height(), geometry.coveredTiles());
    gles::ShadingGeometryPass pass(geometry, tiles, eyes);
    pass.run();
    const int w = geometry.width(), h = geometry.height();
    const auto shading = readTexels(pass.shading().get(), w, h, "usampler2D");
    const auto position = readTexels(pass.position().get(), w, h, "sampler2D");
    const gles::GeometryBuffer::Cube& cube = geometry.cube();
    double worstVector = 0;
    int worstStep = 0;
    std::size_t checked = 0, offObject = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                       static_cast<std::size_t>(x));
            const std::optional<ProjectorPixel> traced = vase.pixels.trace(x, y);
            const float alpha = std::bit_cast<float>(position[i + 3]);
            if (!traced) {
                ASSERT_EQ(alpha, 0.0f) << x << "," << y;
                ++offObject;
                continue;
            }
            ASSERT_EQ(alpha, 1.0f) << x << "," << y;
            const gles::PackedPixel packed = gles::packProjectorPixel(traced);
            for (std::size_t k = 0; k < 3; ++k) {
                // The pass's own float arithmetic on the stored float position.
                const double fraction =
                    (static_cast<double>(packed.geometry0[k]) - cube.low[k]) / cube.side * 1023.0;
                const double got =
                    static_cast<double>(std::bit_cast<float>(position[i + k])) * 1023.0;
                worstStep = std::max(
                    worstStep,
                    static_cast<int>(std::lround(std::fabs(got - std::floor(fraction + 0.5)))));
            }
            const Vec3d& X = traced->point.position;
            const Vec3d& n = traced->point.normal;
            const Vec3d g = gles::decodeOctahedralNormal(packed.geometry1[3]);
            const Vec3d viewer = proto::zoneEye(
                X, g, std::span<const std::array<float, 3>>(eyes.zone),
                Vec3d{static_cast<double>(eyes.viewer[0]), static_cast<double>(eyes.viewer[1]),
                      static_cast<double>(eyes.viewer[2])});
            const Vec3d toViewer =
                proto::normalized(Vec3d{viewer.x - X.x, viewer.y - X.y, viewer.z - X.z});
            const Vec3d m = gles::mirroredViewer(n, toViewer);
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
    std::cout << "shading geometry: " << checked << " pixels, position within " << worstStep
              << " step of the nearest 1/1023 of the cube (side " << cube.side
              << " m), n, m, g within " << worstVector << "; " << offObject
              << " off the object with alpha 0\n";
    EXPECT_GT(checked, static_cast<std::size_t>(w * h / 10));
    EXPECT_GT(offObject, 0u);
    // The shader rounds to the nearest step itself: the texel holds it exactly unless the float
    // arithmetic lands on the other side of a half step.
    EXPECT_LE(worstStep, 1);
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

// What the material pass reads: the test bundle's projector pixels traced, its θs maps (every
// harmonic, as a bundle without a basis) and presets uploaded.
struct MaterialPassInputs : TracedVase {
    proto::ThetaBasis basis = proto::ThetaBasis::full(bundle.view().model().harmonics);
    gles::ThetaTextures textures{bundle.view(), basis, 256, 4096};
    gles::TileCover tiles{geometry.width(), geometry.height(), geometry.coveredTiles()};
};

// One coded material read back and decoded by material_codes.h's C++ side.
struct DecodedMaterial {
    std::vector<std::vector<std::uint32_t>> layers;
    std::vector<std::uint32_t> diffuse;
    int width = 0;
    int basisSize = 0;

    DecodedMaterial(const gles::CodedMaterial& material, const gles::ShaderLayout& layout, int w,
                    int h)
        : width(w), basisSize(layout.basisSize) {
        for (int l = 0; l < layout.materialLayers(); ++l) {
            layers.push_back(readTexels(material.codes.get(), w, h, "isampler2DArray", l));
        }
        diffuse = readTexels(material.diffuse.get(), w, h, "sampler2D");
    }
    std::uint32_t word(int x, int y, int w) const {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                              static_cast<std::size_t>(x);
        return layers[static_cast<std::size_t>(w / 4)][4 * i + static_cast<std::size_t>(w % 4)];
    }
    // The code of value q (thetaMaterialSize order: kd RGB, then u_j RGB).
    int code(int x, int y, int q) const {
        if (q < 3) {
            const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                  static_cast<std::size_t>(x);
            return static_cast<int>(std::lround(static_cast<double>(std::bit_cast<float>(
                                                    diffuse[4 * i + static_cast<std::size_t>(q)])) *
                                                gles::kDiffuseCodeMax));
        }
        const int j = (q - 3) / 3, c = (q - 3) % 3;
        const int perChannel = gles::basisWordsPerChannel(basisSize);
        return gles::unpackSignedBytes(
            word(x, y, c * perChannel + j / 4))[static_cast<std::size_t>(j % 4)];
    }
    float value(const gles::MaterialCoding& coding, int x, int y, int q) const {
        return q < 3 ? coding.diffuse(code(x, y, q)) : coding.basis((q - 3) / 3, code(x, y, q));
    }
    // 1/S and the geometric normal's z.
    std::array<float, 2> extra(int x, int y) const {
        const std::uint32_t w = word(x, y, 3 * gles::basisWordsPerChannel(basisSize));
        return {proto::halfToFloat(static_cast<std::uint16_t>(w & 0xffffu)),
                proto::halfToFloat(static_cast<std::uint16_t>(w >> 16))};
    }
};

// The material pass against its definition: the θs maps sampled bilinearly at the pixel's uv,
// blended by the preset, times the viewer's horizon, coded (material_codes.h): every value
// within half a step of its code plus the maps' half floats; 1/S and the geometric normal's z in
// the word after the codes.
TEST_F(GlesLoadPassesTest, MaterialPassSamplesBlendsAndCodesAsItsDefinition) {
    const MaterialPassInputs in;
    const proto::BundleView& view = in.bundle.view();
    const ProjectorPixels& pixels = in.pixels;
    const gles::GeometryBuffer& geometry = in.geometry;
    const proto::ThetaBasis& basis = in.basis;
    const gles::ThetaTextures& textures = in.textures;
    const std::array<float, 3> viewer = view.settings().viewerPosition;
    gles::MaterialPass pass(textures, geometry, in.tiles, gles::ViewerEyes{viewer, {}});
    const gles::CodedMaterial target = pass.makeTarget();
    const std::size_t preset = 1;  // "radial": half-float weights
    pass.composePreset(target, preset);

    const int w = geometry.width(), h = geometry.height();
    const gles::ShaderLayout& layout = textures.layout();
    const gles::MaterialCoding& coding = textures.coding();
    const DecodedMaterial decoded(target, layout, w, h);
    const int values = layout.materialValues();
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
    double worstSteps = 0, worstExtra = 0;
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
            const Vec3d geometric = gles::decodeOctahedralNormal(packed.geometry1[3]);
            const double horizon = proto::horizonFactor(
                std::min(proto::dot(normal, toViewer), proto::dot(geometric, toViewer)));
            for (int q = 0; q < values; ++q) {
                double expected = 0, magnitude = 0;
                for (std::size_t r = 0; r < maps.size(); ++r) {
                    const double term = bilinear(alpha, tw, th, static_cast<int>(maps.size()),
                                                 static_cast<int>(r), u, v) *
                                        bilinear(maps[r], tw, th, values, q, u, v);
                    expected += term;
                    magnitude += std::fabs(term);
                }
                expected *= horizon;
                const double step =
                    q < 3 ? static_cast<double>(coding.diffuseSpan()) / gles::kDiffuseCodeMax
                          : static_cast<double>(coding.basisStep((q - 3) / 3));
                if (step == 0) {
                    continue;
                }
                // The maps' half floats (2⁻¹¹ of each term) and the filter's weights on top of
                // the coding's half step.
                const double slack = 1e-3 * magnitude * horizon;
                const double error =
                    std::fabs(static_cast<double>(decoded.value(coding, x, y, q)) - expected);
                worstSteps = std::max(worstSteps, (error - slack) / step);
                ++compared;
            }
            const std::array<float, 2> extra = decoded.extra(x, y);
            worstExtra =
                std::max({worstExtra,
                          std::fabs(static_cast<double>(extra[0]) -
                                    static_cast<double>(std::min(packed.geometry0[3], 65504.0f))) /
                              std::max(1.0, std::fabs(static_cast<double>(packed.geometry0[3]))),
                          std::fabs(static_cast<double>(extra[1]) - geometric.z)});
        }
    }
    std::cout << compared << " material values compared: within " << worstSteps
              << " of a code step of their definition beyond the maps' rounding; 1/S and g.z "
                 "within "
              << worstExtra << "\n";
    EXPECT_GT(compared, 10000u);
    EXPECT_LT(worstSteps, 0.5);     // the nearest code
    EXPECT_LT(worstExtra, 1.1e-3);  // half floats, truncated as llvmpipe writes them: ≤ 2⁻¹⁰
}

// Live weights: the regions' coded materials blended by a preset's α in projector space give
// the preset's material as the sampling pass composes it, to within a code (two roundings).
TEST_F(GlesLoadPassesTest, BlendingCodedRegionsGivesThePresetsMaterial) {
    const MaterialPassInputs in;
    const ProjectorPixels& pixels = in.pixels;
    const gles::GeometryBuffer& geometry = in.geometry;
    const gles::ThetaTextures& textures = in.textures;
    gles::MaterialPass pass(textures, geometry, in.tiles,
                            gles::ViewerEyes{in.bundle.view().settings().viewerPosition, {}});
    const gles::WeightPass weights(textures, geometry, in.tiles);
    std::vector<gles::CodedMaterial> regions;
    for (int r = 0; r < textures.layout().regions; ++r) {
        regions.push_back(pass.makeTarget());
        pass.composeRegion(regions.back(), r);
    }
    const int w = geometry.width(), h = geometry.height();
    for (std::size_t preset = 0; preset < textures.presetCount(); ++preset) {
        const gles::CodedMaterial sampled = pass.makeTarget(), blended = pass.makeTarget();
        pass.composePreset(sampled, preset);
        pass.blendRegions(blended, regions, weights.alpha(preset));
        const DecodedMaterial a(sampled, textures.layout(), w, h);
        const DecodedMaterial b(blended, textures.layout(), w, h);
        int worst = 0;
        std::size_t compared = 0;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                if (!pixels.trace(x, y)) {
                    continue;
                }
                for (int q = 0; q < textures.layout().materialValues(); ++q) {
                    worst = std::max(worst, std::abs(a.code(x, y, q) - b.code(x, y, q)));
                    ++compared;
                }
                ASSERT_EQ(a.extra(x, y), b.extra(x, y)) << x << "," << y;
            }
        }
        std::cout << "preset " << preset << ": " << compared << " codes, blended within " << worst
                  << " of sampled\n";
        EXPECT_GT(compared, 10000u);
        EXPECT_LE(worst, 1);
    }
}

}  // namespace
}  // namespace vpe::renderer::testing
