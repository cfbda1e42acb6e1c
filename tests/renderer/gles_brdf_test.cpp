// SPDX-License-Identifier: MIT
// The GLSL Fourier BRDF (fourier_brdf_glsl.h) against proto::evaluateFourierBrdf on random
// coefficients and angles, evaluated by a compute shader (core in ES 3.1) into a buffer.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

#include <GLES3/gl31.h>
#include <gtest/gtest.h>

#include "vpe/proto/fourier_brdf.h"
#include "vpe/proto/reflection_geometry.h"
#include "vpe/renderer/gles/fourier_brdf_glsl.h"
#include "vpe/renderer/gles/gl_program.h"

#include "gles_test_platform.h"

namespace vpe::renderer::testing {
namespace {

using gles::GlObject;

class GlesBrdfTest : public GlesTest {};

enum class Evaluate { kBrdf, kBasis, kAngles };

// Evaluates vpeFourierBrdf — or Σ_k coefficients[k]·basis[k] with vpeFourierBasis — for samples
// of 3·(2M + 2) coefficients (bundle order, 3k + c) and (cos θd, cos θs); or
// vpeReflectionAngles for (n, l, v) triples.
std::vector<float> evaluateOnGpu(int harmonics, const std::vector<float>& inputs, int samples,
                                 int floatsPerSample, Evaluate what) {
    std::string source = "#version 310 es\nprecision highp float;\nprecision highp int;\n";
    source += gles::fourierBrdfGlsl(harmonics);
    source += gles::fourierBasisGlsl(harmonics);
    source += "#define FLOATS " + std::to_string(floatsPerSample) + "\n";
    source += R"GLSL(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
uniform int uSamples;
uniform int uWhat;  // 0 BRDF, 1 basis, 2 angles
void main() {
    int s = int(gl_GlobalInvocationID.x);
    if (s >= uSamples) {
        return;
    }
    int base = s * FLOATS;
    if (uWhat == 2) {
        vec3 n = vec3(inputs[base], inputs[base + 1], inputs[base + 2]);
        vec3 l = vec3(inputs[base + 3], inputs[base + 4], inputs[base + 5]);
        vec3 v = vec3(inputs[base + 6], inputs[base + 7], inputs[base + 8]);
        outputs[s] = vec4(vpeReflectionAngles(n, l, v), 0.0, 0.0);
        return;
    }
    vec3 coefficients[VPE_COEFFICIENTS];
    for (int k = 0; k < VPE_COEFFICIENTS; ++k) {
        coefficients[k] = vec3(inputs[base + 3 * k], inputs[base + 3 * k + 1],
                               inputs[base + 3 * k + 2]);
    }
    int a = base + 3 * VPE_COEFFICIENTS;
    if (uWhat == 0) {
        outputs[s] = vec4(vpeFourierBrdf(coefficients, inputs[a], inputs[a + 1]), 0.0);
        return;
    }
    float basis[VPE_COEFFICIENTS];
    vpeFourierBasis(inputs[a], inputs[a + 1], basis);
    vec3 f = vec3(0.0);
    for (int k = 0; k < VPE_COEFFICIENTS; ++k) {
        f += coefficients[k] * basis[k];
    }
    outputs[s] = vec4(f, 0.0);
}
)GLSL";
    const unsigned shader = gles::compileShader(GL_COMPUTE_SHADER, "brdf_test.comp", source);
    GlObject program = GlObject::program(gles::linkProgram("brdf_test", shader));
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
    glUniform1i(glGetUniformLocation(program.get(), "uWhat"), static_cast<int>(what));
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
    gles::checkGlError("brdf test dispatch");
    return result;
}

void expectMatchesProto(Evaluate what) {
    std::mt19937 random(6);
    std::uniform_real_distribution<float> coefficient(-1.0f, 1.0f), cosine(-1.2f, 1.2f);
    for (int harmonics : {0, 1, 3, 10, 15, 24}) {
        const int k = proto::coefficientCount(harmonics);
        const int floats = 3 * k + 2;
        const int samples = 2000;
        std::vector<float> inputs(static_cast<std::size_t>(samples * floats));
        for (int s = 0; s < samples; ++s) {
            float* sample = inputs.data() + s * floats;
            for (int i = 0; i < 3 * k; ++i) {
                sample[i] = coefficient(random);
            }
            sample[3 * k] = cosine(random);
            sample[3 * k + 1] =
                s < 8 ? std::array<float, 8>{-1, 1, 0, -1.5f, 1.5f, 0.999999f, -0.999999f, 1e-7f}
                            [static_cast<std::size_t>(s)]
                      : cosine(random);
        }
        const std::vector<float> gpu = evaluateOnGpu(harmonics, inputs, samples, floats, what);
        double worst = 0;
        for (int s = 0; s < samples; ++s) {
            const float* sample = inputs.data() + s * floats;
            for (int c = 0; c < 3; ++c) {
                std::vector<float> channel(static_cast<std::size_t>(k));
                double scale = 0;
                for (int i = 0; i < k; ++i) {
                    channel[static_cast<std::size_t>(i)] = sample[3 * i + c];
                    scale += std::fabs(static_cast<double>(sample[3 * i + c]));
                }
                const float expected = proto::evaluateFourierBrdf<float>(
                    channel.data(), harmonics, sample[3 * k], sample[3 * k + 1]);
                const double error =
                    std::fabs(static_cast<double>(gpu[static_cast<std::size_t>(4 * s + c)]) -
                              static_cast<double>(expected)) /
                    (scale + 1e-30);
                worst = std::max(worst, error);
                // The recurrence's rounding grows like m² ulps near θs = 0 and π.
                ASSERT_LE(error, 2e-6 * (1 + harmonics * harmonics))
                    << "M = " << harmonics << ", sample " << s << ", channel " << c << ": GLSL "
                    << gpu[static_cast<std::size_t>(4 * s + c)] << ", proto " << expected;
            }
        }
        std::cout << (what == Evaluate::kBrdf ? "vpeFourierBrdf" : "vpeFourierBasis")
                  << ", M = " << harmonics
                  << ": largest |GLSL − proto| / Σ|coefficients| = " << worst << "\n";
    }
}

TEST_F(GlesBrdfTest, GlslFourierBrdfMatchesProto) {
    expectMatchesProto(Evaluate::kBrdf);
}

// The shading pass evaluates f as Σ_k c_k·basis_k (in the low-rank space too).
TEST_F(GlesBrdfTest, GlslFourierBasisMatchesProto) {
    expectMatchesProto(Evaluate::kBasis);
}

TEST_F(GlesBrdfTest, GlslReflectionAnglesMatchProto) {
    std::mt19937 random(7);
    std::normal_distribution<float> gaussian;
    const int samples = 4000, floats = 9;
    std::vector<float> inputs(static_cast<std::size_t>(samples * floats));
    for (int s = 0; s < samples; ++s) {
        for (int v = 0; v < 3; ++v) {
            const proto::Vec3<float> unit = proto::normalized(
                proto::Vec3<float>{gaussian(random), gaussian(random), gaussian(random)});
            inputs[static_cast<std::size_t>(s * floats + 3 * v)] = unit.x;
            inputs[static_cast<std::size_t>(s * floats + 3 * v + 1)] = unit.y;
            inputs[static_cast<std::size_t>(s * floats + 3 * v + 2)] = unit.z;
        }
    }
    const std::vector<float> gpu = evaluateOnGpu(1, inputs, samples, floats, Evaluate::kAngles);
    for (int s = 0; s < samples; ++s) {
        const float* x = inputs.data() + s * floats;
        const auto angles = proto::reflectionAngles(proto::Vec3<float>{x[0], x[1], x[2]},
                                                    proto::Vec3<float>{x[3], x[4], x[5]},
                                                    proto::Vec3<float>{x[6], x[7], x[8]});
        ASSERT_NEAR(gpu[static_cast<std::size_t>(4 * s)], angles.cosThetaD, 1e-6f) << s;
        ASSERT_NEAR(gpu[static_cast<std::size_t>(4 * s + 1)], angles.cosThetaS, 4e-6f) << s;
    }
}

}  // namespace
}  // namespace vpe::renderer::testing
