// SPDX-License-Identifier: MIT
// Each GLSL mirror of a C++ step the frame takes, against its C++ side, one test each: the
// horizon, the reflection angles, the θs table parameter and the table lookup, the octahedral
// normal, the relief's detail normal, the projector's response inverse. Evaluated by a compute
// shader (core in ES 3.1) into a buffer.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <GLES3/gl31.h>
#include <gtest/gtest.h>

#include "vpe/proto/detail_normal.h"
#include "vpe/proto/half_float.h"
#include "vpe/proto/reflection_geometry.h"
#include "vpe/proto/response_function.h"
#include "vpe/proto/surface_horizon.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/renderer/cpu/material_textures.h"
#include "vpe/renderer/cpu/measured_light.h"

#include "gl_program.h"
#include "gles_test_platform.h"
#include "material_codes.h"
#include "shading_glsl.h"

namespace vpe::renderer::testing {
namespace {

using gles::GlObject;

class GlesShadingGlslTest : public GlesTest {};

// Runs `body` (GLSL computing `vec4 result` from `float in[]` at `base = s * FLOATS` and
// `uint bits[]` at the same base) once per sample; returns 4 floats per sample. `prelude` is
// pasted before main (the functions under test, uniforms).
std::vector<float> runOnGpu(const std::string& prelude, const std::string& body,
                            const std::vector<float>& inputs, int floatsPerSample) {
    const int samples = static_cast<int>(inputs.size()) / floatsPerSample;
    std::string source =
        "#version 310 es\nprecision highp float;\nprecision highp int;\n"
        "precision highp sampler2D;\n";
    source += prelude;
    source += "#define FLOATS " + std::to_string(floatsPerSample) + "\n";
    source += R"GLSL(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { float in_[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 out_[]; };
uniform int uSamples;
void main() {
    int s = int(gl_GlobalInvocationID.x);
    if (s >= uSamples) {
        return;
    }
    int base = s * FLOATS;
    vec4 result = vec4(0.0);
)GLSL";
    source += body;
    source += "    out_[s] = result;\n}\n";
    const unsigned shader = gles::compileShader(GL_COMPUTE_SHADER, "shading_test.comp", source);
    GlObject program = GlObject::program(gles::linkProgram("shading_test", shader));
    GlObject in = GlObject::buffer(), out = GlObject::buffer();
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, in.get());
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(inputs.size() * sizeof(float)),
                 inputs.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.get());
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, out.get());
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(samples * 4 * sizeof(float)),
                 nullptr, GL_STATIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.get());
    glUseProgram(program.get());
    glUniform1i(glGetUniformLocation(program.get(), "uSamples"), samples);
    glDispatchCompute(static_cast<GLuint>((samples + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> result(static_cast<std::size_t>(samples) * 4);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, out.get());
    const void* mapped =
        glMapBufferRange(GL_SHADER_STORAGE_BUFFER, 0,
                         static_cast<GLsizeiptr>(result.size() * sizeof(float)), GL_MAP_READ_BIT);
    EXPECT_NE(mapped, nullptr);
    if (mapped != nullptr) {
        std::memcpy(result.data(), mapped, result.size() * sizeof(float));
        glUnmapBuffer(GL_SHADER_STORAGE_BUFFER);
    }
    gles::checkGlError("shading test dispatch");
    return result;
}

// The material's codes (material_codes.h): words of four signed bytes unpacked and packed as
// the C++ side does, bit for bit, and values coded by the material pass's expression as
// MaterialCoding codes them.
TEST_F(GlesShadingGlslTest, MaterialCodesMatchTheirCppSide) {
    std::mt19937 random(31);
    std::uniform_int_distribution<std::uint32_t> anyWord;
    std::uniform_int_distribution<int> anyCode(-gles::kBasisCodeMax, gles::kBasisCodeMax);
    std::uniform_real_distribution<float> anyValue(-0.75f, 0.75f);
    gles::MaterialCoding coding(1);
    const std::vector<float> texel{0.0f, 0.1f, 0.3f, -0.75f, 0.5f, 0.25f};  // kd RGB, u_0 RGB
    coding.cover(texel);
    const float inverseStep = 1.0f / coding.basisStep(0);
    const int samples = 4000;
    std::vector<std::uint32_t> words;
    std::vector<float> inputs;
    for (int i = 0; i < samples; ++i) {
        std::uint32_t word = anyWord(random);
        while (((word >> 23) & 0xffu) == 0xffu) {  // not a NaN's bits: they pass through floats
            word = anyWord(random);
        }
        words.push_back(word);
        inputs.push_back(std::bit_cast<float>(word));
        std::array<int, 4> codes{};
        do {  // whose packed word is no NaN's bits either (it comes back as a float)
            for (int& code : codes) {
                code = anyCode(random);
            }
        } while (((gles::packSignedBytes(codes) >> 23) & 0xffu) == 0xffu);
        for (const int code : codes) {
            inputs.push_back(static_cast<float>(code));
        }
        inputs.push_back(anyValue(random));
    }
    const std::string prelude = gles::materialCodesGlsl() +
                                "const float INVERSE_STEP = " + gles::glslFloat(inverseStep) +
                                ";\n";
    const std::vector<float> unpacked =
        runOnGpu(prelude, "    result = vpeSignedBytes(floatBitsToInt(in_[base]));\n", inputs, 6);
    const std::vector<float> packed = runOnGpu(
        prelude,
        "    result.x = intBitsToFloat(vpePackSignedBytes(vec4(in_[base + 1], in_[base + 2], "
        "in_[base + 3], in_[base + 4])));\n"
        "    result.y = clamp(floor(in_[base + 5] * INVERSE_STEP + 0.5), -127.0, 127.0);\n",
        inputs, 6);
    for (int i = 0; i < samples; ++i) {
        const auto s = static_cast<std::size_t>(i);
        const std::array<int, 4> bytes = gles::unpackSignedBytes(words[s]);
        for (std::size_t b = 0; b < 4; ++b) {
            ASSERT_EQ(unpacked[4 * s + b], static_cast<float>(bytes[b])) << std::hex << words[s];
        }
        std::array<int, 4> codes{};
        for (std::size_t b = 0; b < 4; ++b) {
            codes[b] = static_cast<int>(inputs[6 * s + 1 + b]);
        }
        ASSERT_EQ(std::bit_cast<std::uint32_t>(packed[4 * s]), gles::packSignedBytes(codes));
        ASSERT_EQ(gles::unpackSignedBytes(gles::packSignedBytes(codes)), codes);
        ASSERT_EQ(packed[4 * s + 1], static_cast<float>(coding.basisCode(0, inputs[6 * s + 5])))
            << inputs[6 * s + 5];
    }
    // Codes decode to within half a step of what they code, in range.
    for (int i = 0; i < samples; ++i) {
        const float u = inputs[6 * static_cast<std::size_t>(i) + 5];
        ASSERT_LE(std::fabs(coding.basis(0, coding.basisCode(0, u)) - u),
                  0.5f * coding.basisStep(0) * 1.0001f);
    }
    EXPECT_EQ(coding.diffuseCode(0.0f), 0);
    EXPECT_EQ(coding.diffuseCode(0.3f), gles::kDiffuseCodeMax);
    EXPECT_FLOAT_EQ(coding.diffuse(gles::kDiffuseCodeMax), 0.3f);
    EXPECT_FLOAT_EQ(coding.basisStep(0), 0.75f / gles::kBasisCodeMax);
}

TEST_F(GlesShadingGlslTest, HorizonFactorMatchesProto) {
    std::vector<float> inputs;
    for (int i = -200; i <= 1200; ++i) {
        inputs.push_back(static_cast<float>(i) * 1e-4f);  // the ramp, finely, and beyond
    }
    inputs.push_back(-1.0f);
    inputs.push_back(1.0f);
    const std::vector<float> gpu = runOnGpu(
        gles::shadingStepsGlsl(), "    result.x = vpeHorizonFactor(in_[base]);\n", inputs, 1);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        ASSERT_NEAR(gpu[4 * i], proto::horizonFactor(inputs[i]), 2e-6f) << inputs[i];
    }
    EXPECT_EQ(gpu[0], 0.0f);
    EXPECT_EQ(gpu[4 * (inputs.size() - 1)], 1.0f);
}

// 4000 samples of three random unit vectors (n, l, v), nine floats each, from `seed`.
std::vector<float> randomUnitTriples(unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<float> gaussian;
    std::vector<float> inputs;
    for (int s = 0; s < 4000; ++s) {
        for (int v = 0; v < 3; ++v) {
            const auto unit = proto::normalized(
                proto::Vec3<float>{gaussian(random), gaussian(random), gaussian(random)});
            inputs.insert(inputs.end(), {unit.x, unit.y, unit.z});
        }
    }
    return inputs;
}

// A gamma per channel and a measured curve per channel (the curve's own sample counts): the
// two response kinds the projector-level steps are checked with.
std::pair<proto::ResponseCurves, proto::ResponseCurves> testResponses() {
    proto::ResponseCurves gamma;
    gamma.gamma = {2.2f, 2.0f, 2.6f};
    proto::ResponseCurves curve;
    curve.kind = proto::ResponseKind::kCurve;
    curve.curve = {std::vector<float>{0.02f, 0.1f, 0.3f, 0.6f, 1.0f},
                   std::vector<float>{0.0f, 0.2f, 0.5f, 1.0f},
                   std::vector<float>{0.05f, 0.05f, 0.4f, 0.9f, 1.1f, 1.2f}};
    return {gamma, curve};
}

TEST_F(GlesShadingGlslTest, ReflectionAnglesMatchProto) {
    const std::vector<float> inputs = randomUnitTriples(7);
    const std::vector<float> gpu = runOnGpu(gles::shadingStepsGlsl(), R"GLSL(
    vec3 n = vec3(in_[base], in_[base + 1], in_[base + 2]);
    vec3 l = vec3(in_[base + 3], in_[base + 4], in_[base + 5]);
    vec3 v = vec3(in_[base + 6], in_[base + 7], in_[base + 8]);
    result.xy = vpeReflectionAngles(n, l, v);
)GLSL",
                                            inputs, 9);
    for (std::size_t s = 0; s < inputs.size() / 9; ++s) {
        const float* x = inputs.data() + 9 * s;
        const auto angles = proto::reflectionAngles(proto::Vec3<float>{x[0], x[1], x[2]},
                                                    proto::Vec3<float>{x[3], x[4], x[5]},
                                                    proto::Vec3<float>{x[6], x[7], x[8]});
        ASSERT_NEAR(gpu[4 * s], angles.cosThetaD, 1e-6f) << s;
        ASSERT_NEAR(gpu[4 * s + 1], angles.cosThetaS, 4e-6f) << s;
    }
}

// The frame's cos θs from the mirrored viewer m = 2(n·v)n − v (packed at load as half floats)
// against proto::reflectionAngles: vpeMirroredViewer against mirroredViewer in double, then
// (n·l, l·m) against (cos θd, cos θs) where proto does not clamp, for m in float and in halves.
TEST_F(GlesShadingGlslTest, MirroredViewerGivesTheReflectionAngles) {
    const std::vector<float> inputs = randomUnitTriples(17);
    const std::vector<float> mirrored = runOnGpu(gles::shadingStepsGlsl(), R"GLSL(
    vec3 n = vec3(in_[base], in_[base + 1], in_[base + 2]);
    vec3 v = vec3(in_[base + 6], in_[base + 7], in_[base + 8]);
    result.xyz = vpeMirroredViewer(n, v);
)GLSL",
                                                 inputs, 9);
    const std::vector<float> angles = runOnGpu(gles::shadingStepsGlsl(), R"GLSL(
    vec3 n = vec3(in_[base], in_[base + 1], in_[base + 2]);
    vec3 l = vec3(in_[base + 3], in_[base + 4], in_[base + 5]);
    vec3 v = vec3(in_[base + 6], in_[base + 7], in_[base + 8]);
    vec3 m = vpeMirroredViewer(n, v);
    vec2 exact = vpeMirroredReflectionAngles(n, l, m);
    // As the frame reads them: n and m through packHalf2x16.
    vec3 nh = vec3(unpackHalf2x16(packHalf2x16(n.xy)), unpackHalf2x16(packHalf2x16(n.zz)).x);
    vec3 mh = vec3(unpackHalf2x16(packHalf2x16(m.xy)), unpackHalf2x16(packHalf2x16(m.zz)).x);
    result = vec4(exact, vpeMirroredReflectionAngles(nh, l, mh));
)GLSL",
                                               inputs, 9);
    double worstHalf = 0;
    for (std::size_t s = 0; s < inputs.size() / 9; ++s) {
        const float* x = inputs.data() + 9 * s;
        const Vec3d n{x[0], x[1], x[2]}, v{x[6], x[7], x[8]};
        const Vec3d m = gles::mirroredViewer(n, v);
        ASSERT_NEAR(mirrored[4 * s], m.x, 2e-6) << s;
        ASSERT_NEAR(mirrored[4 * s + 1], m.y, 2e-6) << s;
        ASSERT_NEAR(mirrored[4 * s + 2], m.z, 2e-6) << s;
        const auto reference = proto::reflectionAngles(proto::Vec3<float>{x[0], x[1], x[2]},
                                                       proto::Vec3<float>{x[3], x[4], x[5]},
                                                       proto::Vec3<float>{x[6], x[7], x[8]});
        ASSERT_NEAR(angles[4 * s], reference.cosThetaD, 1e-6f) << s;
        // proto clamps cos θs to [−1, 1]; the table coordinate clips it the same way.
        ASSERT_NEAR(std::clamp(angles[4 * s + 1], -1.0f, 1.0f), reference.cosThetaS, 4e-6f) << s;
        worstHalf = std::max(
            worstHalf, static_cast<double>(std::fabs(std::clamp(angles[4 * s + 3], -1.0f, 1.0f) -
                                                     reference.cosThetaS)));
    }
    std::cout << "cos θs from half-float n and m: largest error " << worstHalf << "\n";
    EXPECT_LT(worstHalf, 1.5e-3);  // three products of components rounded to 2⁻¹¹ relative
}

TEST_F(GlesShadingGlslTest, ThetaTableParameterMatchesProto) {
    std::vector<float> inputs;
    for (int i = -1000; i <= 1000; ++i) {
        inputs.push_back(static_cast<float>(i) / 1000.0f);
    }
    inputs.insert(inputs.end(), {1e-7f, -1e-7f, 0.9999999f, -0.9999999f});
    const std::vector<float> gpu = runOnGpu(
        gles::shadingStepsGlsl(), "    result.x = vpeThetaTableParameter(in_[base]);\n", inputs, 1);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        ASSERT_NEAR(gpu[4 * i], proto::thetaTableParameter(inputs[i]), 1e-6f) << inputs[i];
    }
    // The frame's folded form, for a 1024-sample table.
    const float scale = 1023.0f / 1024.0f, offset = 0.5f / 1024.0f;
    const std::vector<float> folded =
        runOnGpu(gles::shadingStepsGlsl(),
                 "    result.x = vpeThetaTableCoordinate(in_[base], " + gles::glslFloat(scale) +
                     ", " + gles::glslFloat(offset) + ");\n",
                 inputs, 1);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        ASSERT_NEAR(folded[4 * i], proto::thetaTableParameter(inputs[i]) * scale + offset, 1e-6f)
            << inputs[i];
    }
}

TEST_F(GlesShadingGlslTest, OctahedralNormalMatchesItsCppDecoding) {
    std::mt19937 random(11);
    std::normal_distribution<double> gaussian;
    std::vector<Vec3d> normals{{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0.6, 0, -0.8}};
    for (int i = 0; i < 4000; ++i) {
        normals.push_back(
            proto::normalized(Vec3d{gaussian(random), gaussian(random), gaussian(random)}));
    }
    std::vector<float> inputs;
    for (const Vec3d& n : normals) {
        inputs.push_back(std::bit_cast<float>(gles::encodeOctahedralNormal(n)));
    }
    const std::vector<float> gpu =
        runOnGpu(gles::shadingStepsGlsl(),
                 "    result.xyz = vpeOctahedralNormal(floatBitsToUint(in_[base]));\n", inputs, 1);
    double worstAngle = 0;
    for (std::size_t i = 0; i < normals.size(); ++i) {
        const Vec3d cpu = gles::decodeOctahedralNormal(gles::encodeOctahedralNormal(normals[i]));
        ASSERT_NEAR(gpu[4 * i], cpu.x, 2e-6) << i;
        ASSERT_NEAR(gpu[4 * i + 1], cpu.y, 2e-6) << i;
        ASSERT_NEAR(gpu[4 * i + 2], cpu.z, 2e-6) << i;
        worstAngle = std::max(worstAngle, std::acos(std::min(1.0, proto::dot(cpu, normals[i]))));
    }
    std::cout << "octahedral normals: largest angular error " << worstAngle << " rad\n";
    EXPECT_LT(worstAngle, 7e-5);  // measured 5.9e-5: 16 bits per coordinate
}

// The table as the renderer uploads it (RGBA16F, linear filtering, sample s at texel s)
// against proto::ThetaTable::sample on the same (half-rounded) values.
TEST_F(GlesShadingGlslTest, ThetaTableLookupMatchesProto) {
    const proto::ThetaBasis basis = proto::ThetaBasis::full(1);  // 1/√2, cos θ, sin θ
    const int samples = 64;
    const proto::ThetaTable table = proto::ThetaTable::of(basis, samples);
    std::vector<float> texels(static_cast<std::size_t>(samples) * 4, 0.0f);
    for (int s = 0; s < samples; ++s) {
        for (int j = 0; j < table.size; ++j) {
            texels[static_cast<std::size_t>(4 * s + j)] =
                table.values[static_cast<std::size_t>(s * table.size + j)];
        }
    }
    // RGBA32F keeps the values exact, so that the comparison measures the filtering alone.
    GlObject texture = gles::makeTexture2D(GL_RGBA32F, samples, 1, GL_RGBA, GL_FLOAT, texels.data(),
                                           gles::TextureFilter::kLinear);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture.get());
    std::vector<float> inputs;
    for (int i = -500; i <= 500; ++i) {
        inputs.push_back(static_cast<float>(i) / 500.0f);
    }
    const std::string prelude = gles::shadingStepsGlsl() + "uniform highp sampler2D uTable;\n";
    const std::string scale = gles::glslFloat((samples - 1.0f) / samples);
    const std::string offset = gles::glslFloat(0.5f / samples);
    const std::vector<float> gpu =
        runOnGpu(prelude,
                 "    float x = vpeThetaTableParameter(in_[base]) * " + scale + " + " + offset +
                     ";\n" + "    result = texture(uTable, vec2(x, 0.5));\n",
                 inputs, 1);
    double worst = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const double x = proto::thetaTableParameter(static_cast<double>(inputs[i]));
        for (int j = 0; j < table.size; ++j) {
            const double error = std::fabs(
                static_cast<double>(gpu[4 * i + static_cast<std::size_t>(j)]) - table.sample(j, x));
            worst = std::max(worst, error);
        }
    }
    std::cout << "θs table lookup, 64 samples: largest |GLSL − proto| " << worst << "\n";
    // llvmpipe weighs the two samples in float (measured 3.5e-7). A GPU with 8-bit subtexel
    // weights would be off by up to the step between samples (≤ 0.05 here) times 2⁻⁹.
    EXPECT_LT(worst, 1e-6);
}

// vpeProjectorLevel against ResponseFunction::level with compensatePixel's clipping, the
// function made from the same curves as the CPU reference makes it (responseFunctionOf).
// The response inverse as the frame reads it: projectorLevelTable uploaded as RGBA16F, looked up
// through GL_LINEAR by vpeProjectorLevelTable at r·(N − 1)/N, against projectorLevelFromTable
// (the same interpolation in double) and against the exact inverse with compensatePixel's
// clipping (the table's own error: largest in the first interval, where r^(1/γ) is steepest).
TEST_F(GlesShadingGlslTest, ProjectorLevelTableMatchesTheResponseInverse) {
    std::vector<float> inputs;
    for (int i = -100; i <= 1300; ++i) {
        inputs.push_back(static_cast<float>(i) / 1000.0f);
    }
    for (int i = 1; i <= 200; ++i) {
        inputs.push_back(static_cast<float>(i) * 2.5e-6f);  // the first samples, finely
    }
    const auto [gamma, curve] = testResponses();
    const int samples = gles::kProjectorLevelSamples;
    const float scale = static_cast<float>(samples - 1) / static_cast<float>(samples);
    for (const proto::ResponseCurves& response : {gamma, curve}) {
        const std::vector<float> table = gles::projectorLevelTable(response, samples);
        std::vector<std::uint16_t> texels(4 * static_cast<std::size_t>(samples), 0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(samples); ++i) {
            for (std::size_t c = 0; c < 3; ++c) {
                texels[4 * i + c] = proto::floatToHalf(table[3 * i + c]);
            }
        }
        GlObject texture = gles::makeTexture2D(GL_RGBA16F, samples, 1, GL_RGBA, GL_HALF_FLOAT,
                                               texels.data(), gles::TextureFilter::kLinear);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, texture.get());
        const std::vector<float> gpu =
            runOnGpu(gles::projectorLevelTableGlsl(samples),
                     "    result.xyz = vpeProjectorLevelTable(vec3(in_[base]) * " +
                         gles::glslFloat(scale) + ");\n",
                     inputs, 1);
        const proto::ResponseFunction cpu = proto::responseFunctionOf(response);
        double worstLookup = 0, worstTable = 0, worstAbove = 0;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            for (int c = 0; c < 3; ++c) {
                const double r = inputs[i];
                const double fromTable = gles::projectorLevelFromTable(table, c, r);
                worstLookup = std::max(
                    worstLookup,
                    std::fabs(static_cast<double>(gpu[4 * i + static_cast<std::size_t>(c)]) -
                              fromTable));
                const double exact =
                    r > 1.0 ? 1.0 : (r < cpu.blackLevel(c) ? 0.0 : cpu.level(c, r));
                const double error = std::fabs(fromTable - exact);
                worstTable = std::max(worstTable, error);
                if (r >= 2.0 / (samples - 1)) {
                    worstAbove = std::max(worstAbove, error);
                }
            }
        }
        const char* kind = response.kind == proto::ResponseKind::kGamma ? "gamma" : "curve";
        std::cout << kind << " level table: lookup against projectorLevelFromTable " << worstLookup
                  << ", table against the inverse " << worstTable << " (" << worstAbove
                  << " past the first interval)\n";
        EXPECT_LT(worstLookup, 2e-6) << kind;  // llvmpipe filters halves in float
        // Measured 1.4e-2 (3.5 of 255 levels) for γ = 2.6 below r = 1/4095, where r^(1/γ) is
        // steepest (drive levels under 10); 2.4e-4 past it: half-float rounding.
        EXPECT_LT(worstTable, 1.5e-2) << kind;
        EXPECT_LT(worstAbove, 3e-4) << kind;
    }
}

// The weight pass's filter: vpeBilinearWeight on an 8-bit weight array (as a preset uploads it)
// against renderer::bilinearFootprint on the same values, clamping and wrapping in u, at
// coordinates inside, on and past the edges and on texel centres.
TEST_F(GlesShadingGlslTest, BilinearWeightMatchesTheCpuFootprint) {
    const int width = 7, height = 5, layers = 2;
    std::vector<std::uint8_t> texels(static_cast<std::size_t>(width * height * layers));
    for (std::size_t i = 0; i < texels.size(); ++i) {
        texels[i] = static_cast<std::uint8_t>((i * 97 + 13) % 256);
    }
    GlObject texture =
        gles::makeArrayTexture(GL_R8, width, height, layers, GL_RED, GL_UNSIGNED_BYTE,
                               texels.data(), gles::TextureFilter::kNearest);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_ARRAY, texture.get());
    std::mt19937 random(23);
    std::uniform_real_distribution<float> coordinate(-0.3f, 1.3f);
    std::vector<float> inputs;  // s, t, layer
    for (int i = 0; i < 3000; ++i) {
        inputs.insert(inputs.end(),
                      {coordinate(random), coordinate(random), static_cast<float>(i % layers)});
    }
    for (int x = 0; x < width; ++x) {  // texel centres and the seams between them
        for (const float offset : {0.5f, 0.0f}) {
            inputs.insert(inputs.end(), {(static_cast<float>(x) + offset) / width, 0.5f, 1.0f});
        }
    }
    for (const bool wrap : {false, true}) {
        const std::vector<float> gpu = runOnGpu(
            gles::bilinearWeightGlsl() + "uniform highp sampler2DArray uWeights;\n",
            std::string(
                "    result.x = vpeBilinearWeight(uWeights, vec2(in_[base], in_[base + 1]), "
                "int(in_[base + 2]), ") +
                (wrap ? "true" : "false") + ");\n",
            inputs, 3);
        double worst = 0;
        for (std::size_t i = 0; i < inputs.size() / 3; ++i) {
            // The bundle's uv has v up: the GL coordinate t is 1 − v.
            const Vec2d uv{inputs[3 * i], 1.0 - static_cast<double>(inputs[3 * i + 1])};
            const auto layer = static_cast<std::size_t>(inputs[3 * i + 2]);
            const BilinearFootprint taps = bilinearFootprint(width, height, uv, wrap);
            double expected = 0;
            for (int k = 0; k < 4; ++k) {
                expected +=
                    taps.weight[k] *
                    texels[layer * static_cast<std::size_t>(width * height) + taps.texel[k]] /
                    255.0;
            }
            worst = std::max(worst, std::fabs(static_cast<double>(gpu[4 * i]) - expected));
        }
        std::cout << (wrap ? "wrapping" : "clamping") << " bilinear weight: largest |GLSL − CPU| "
                  << worst << "\n";
        EXPECT_LT(worst, 2e-6) << (wrap ? "wrapping" : "clamping");
    }
}

TEST_F(GlesShadingGlslTest, ReliefStepsMatchProto) {
    // A random frame (t, b, n) from a normal and two tangents, and a stored detail normal's
    // x, y (some past the unit disc): the relief pass's normal against proto's in double.
    std::mt19937 random(11);
    std::normal_distribution<float> gaussian;
    std::uniform_real_distribution<float> uniform(-0.8f, 0.8f);
    std::vector<float> inputs;
    std::vector<proto::Vec3d> expected;
    for (int s = 0; s < 4000; ++s) {
        const auto n =
            proto::normalized(proto::Vec3d{gaussian(random), gaussian(random), gaussian(random)});
        const proto::Vec3d du{gaussian(random), gaussian(random), gaussian(random)};
        const proto::Vec3d dv{gaussian(random), gaussian(random), gaussian(random)};
        const proto::TangentFrame<double> frame = proto::tangentFrame(n, du, dv);
        const float x = uniform(random), y = uniform(random);
        for (const proto::Vec3d& v : {frame.t, frame.b, frame.n}) {
            inputs.insert(inputs.end(), {static_cast<float>(v.x), static_cast<float>(v.y),
                                         static_cast<float>(v.z)});
        }
        inputs.insert(inputs.end(), {x, y});
        expected.push_back(proto::applyDetailNormal(
            frame, proto::detailNormalFromXy(static_cast<double>(x), static_cast<double>(y))));
    }
    const std::vector<float> gpu = runOnGpu(gles::reliefStepsGlsl(), R"GLSL(
    vec3 t = vec3(in_[base], in_[base + 1], in_[base + 2]);
    vec3 b = vec3(in_[base + 3], in_[base + 4], in_[base + 5]);
    vec3 n = vec3(in_[base + 6], in_[base + 7], in_[base + 8]);
    vec3 d = vpeDetailNormalFromXy(vec2(in_[base + 9], in_[base + 10]));
    result.xyz = vpeApplyDetailNormal(t, b, n, d);
)GLSL",
                                            inputs, 11);
    float worst = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        worst = std::max({worst, std::fabs(gpu[4 * i] - static_cast<float>(expected[i].x)),
                          std::fabs(gpu[4 * i + 1] - static_cast<float>(expected[i].y)),
                          std::fabs(gpu[4 * i + 2] - static_cast<float>(expected[i].z))});
    }
    std::cout << "relief: largest component difference " << worst << "\n";
    EXPECT_LT(worst, 2e-6f);
}

TEST_F(GlesShadingGlslTest, ProjectorLevelMatchesTheResponseInverse) {
    std::vector<float> inputs;
    for (int i = -100; i <= 1300; ++i) {
        inputs.push_back(static_cast<float>(i) / 1000.0f);  // relative outputs, clipped both ways
    }
    const auto [gamma, curve] = testResponses();
    for (const proto::ResponseCurves& response : {gamma, curve}) {
        const std::vector<float> gpu =
            runOnGpu(gles::projectorLevelGlsl(response),
                     "    result.xyz = vpeProjectorLevel(vec3(in_[base]));\n", inputs, 1);
        const proto::ResponseFunction cpu = proto::responseFunctionOf(response);
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            for (int c = 0; c < 3; ++c) {
                const double r = inputs[i];
                // compensatePixel: above 1 → 1, below the black level → 0, else the inverse.
                const double expected =
                    r > 1.0 ? 1.0 : (r < cpu.blackLevel(c) ? 0.0 : cpu.level(c, r));
                ASSERT_NEAR(gpu[4 * i + static_cast<std::size_t>(c)], expected, 2e-5)
                    << (response.kind == proto::ResponseKind::kGamma ? "gamma" : "curve")
                    << " channel " << c << " at r = " << r;
            }
        }
    }
}

// vpeMeasuredOutputs then vpeProjectorLevel against compensateMeasuredPixel: the inverse of
// the measured model, the highlight's roll-off, the floor, an unmeasured channel.
TEST_F(GlesShadingGlslTest, MeasuredLightMatchesItsCompensation) {
    const std::array<double, 9> mixing{1, 0.076, 0.011, 0.068, 1, 0.057, 0.011, 0.097, 1};
    const std::array<double, 9> inverse = inverse3x3(mixing);
    proto::ResponseCurves curve;
    curve.kind = proto::ResponseKind::kCurve;
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i <= 32; ++i) {
            curve.curve[static_cast<std::size_t>(c)].push_back(
                static_cast<float>(std::pow(i / 32.0, 2.0 + 0.3 * c)));
        }
    }
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<float> inputs;  // target, F, D per sample
    for (int s = 0; s < 4000; ++s) {
        const float scale = s % 4 == 0 ? 2.0f : 0.4f;  // some past the knee
        for (int c = 0; c < 3; ++c) {
            inputs.push_back(scale * unit(random));
        }
        for (int c = 0; c < 3; ++c) {
            inputs.push_back(s % 97 == 0 && c == 1 ? 0.0f : 0.2f + 0.6f * unit(random));
        }
        for (int c = 0; c < 3; ++c) {
            inputs.push_back(0.05f * unit(random));
        }
    }
    const proto::ResponseFunction response = proto::responseFunctionOf(curve);
    const proto::InverseResponseTable table(response, 256);
    std::vector<std::uint16_t> texels(4 * 256, 0);
    for (int i = 0; i < 256; ++i) {
        for (int c = 0; c < 3; ++c) {
            texels[static_cast<std::size_t>(4 * i + c)] =
                proto::floatToHalf(table.levels(c)[static_cast<std::size_t>(i)]);
        }
    }
    GlObject texture = gles::makeTexture2D(GL_RGBA16F, 256, 1, GL_RGBA, GL_HALF_FLOAT,
                                           texels.data(), gles::TextureFilter::kLinear);
    glActiveTexture(GL_TEXTURE0);  // uInverseResponse's default unit
    glBindTexture(GL_TEXTURE_2D, texture.get());
    std::string prelude = gles::measuredLightGlsl(256);
    prelude += "const mat3 kMixingInverse = mat3(";
    for (int column = 0; column < 3; ++column) {
        for (int row = 0; row < 3; ++row) {
            prelude += (column + row == 0 ? "" : ", ") +
                       gles::glslFloat(
                           static_cast<float>(inverse[static_cast<std::size_t>(3 * row + column)]));
        }
    }
    prelude += ");\n";
    const std::vector<float> gpu = runOnGpu(
        prelude,
        "    vec3 target = vec3(in_[base], in_[base + 1], in_[base + 2]);\n"
        "    vec3 f = vec3(in_[base + 3], in_[base + 4], in_[base + 5]);\n"
        "    vec3 d = vec3(in_[base + 6], in_[base + 7], in_[base + 8]);\n"
        "    result.xyz = vpeMeasuredLevel(vpeMeasuredOutputs(target, f, d, kMixingInverse));\n",
        inputs, 9);
    std::array<double, 9> inverseOfFloats{};
    for (std::size_t i = 0; i < 9; ++i) {
        inverseOfFloats[i] = static_cast<double>(static_cast<float>(inverse[i]));
    }
    int rolled = 0, floored = 0;
    for (std::size_t s = 0; 9 * s < inputs.size(); ++s) {
        const float* in = &inputs[9 * s];
        const std::array<double, 3> target{in[0], in[1], in[2]};
        const CompensatedPixel cpu =
            compensateMeasuredPixel(in + 3, in + 6, inverseOfFloats, table, target, 1.0);
        rolled += cpu.clippedHigh ? 1 : 0;
        floored += cpu.clippedLow ? 1 : 0;
        for (std::size_t c = 0; c < 3; ++c) {
            // Float against double through a steep inverse near black: a few 1e-4 of a level.
            ASSERT_NEAR(gpu[4 * s + c], cpu.level[c], 3e-4) << "sample " << s << " channel " << c;
        }
    }
    EXPECT_GT(rolled, 500);
    EXPECT_GT(floored, 50);
}

}  // namespace
}  // namespace vpe::renderer::testing
