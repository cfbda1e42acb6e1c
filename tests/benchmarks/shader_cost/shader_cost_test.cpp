// SPDX-License-Identifier: MIT
// vpe_shader_cost's counts on tiny fragment shaders whose costs are known by hand, and the
// command's output and its refusals of bad input.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "roofline.h"
#include "shader_analysis.h"
#include "shader_compiler.h"
#include "support/cli_expectations.h"
#include "support/command_runner.h"
#include "support/test_data.h"
#include "texture_formats.h"

namespace vpe::shader_cost {
namespace {

const char* const kHeader = R"(#version 310 es
precision highp float;
precision highp int;
layout(location = 0) out vec4 outColor;
uniform vec3 uA;
uniform vec3 uB;
uniform float uX;
uniform int uN;
)";

ShaderReport analyze(const std::string& body) {
    const ShaderCompiler compiler;
    return analyzeShader(compiler, kHeader + body, "test.frag");
}

TEST(ShaderCost, CountsTextureMultiplyAddInverseSqrtAndPow) {
    const ShaderReport report = analyze(R"(
uniform sampler2D uTexture;
uniform vec2 uUv;
uniform vec3 uExponent;
void main() {
    vec3 texel = texture(uTexture, uUv).rgb;  // 1 fetch
    vec3 lit = texel * uA + uB;               // vec3 multiply-add: 6 FLOPs
    float r = inversesqrt(uX);                // 1 SFU
    vec3 shaped = pow(lit, uExponent);        // 3 FLOPs + 6 SFU
    outColor = vec4(shaped * r, 1.0);         // 3 FLOPs
}
)");
    EXPECT_EQ(report.perPixel.flops(), 12);
    EXPECT_EQ(report.perPixel.intOps, 0);
    EXPECT_EQ(report.perPixel.sfu, 7);
    EXPECT_EQ(report.perPixel.flopEquivalent(), 12 + 4 * 7);
    EXPECT_EQ(report.perPixel.textureFetches, 1);
    EXPECT_EQ(report.perPixel.fetchesWithoutFormat, 1);
    EXPECT_FALSE(report.hasDynamicLoops);
    EXPECT_TRUE(report.uncountedOpcodes.empty());
}

TEST(ShaderCost, TakesTheMoreExpensiveSideOfABranch) {
    for (const char* condition : {"uX > 0.0", "uX <= 0.0"}) {
        const std::string body = std::string("void main() {\n    vec3 v;\n    if (") + condition +
                                 R"() {
        v = uA * uB * uA * uB;  // 9
    } else {
        v = uA + uB;            // 3
    }
    outColor = vec4(v, 1.0);
}
)";
        const ShaderReport report = analyze(body);
        EXPECT_EQ(report.perPixel.flops(), 1 + 9) << condition;  // the compare and the products
    }
}

TEST(ShaderCost, CountsTheShadingPathNotAnEarlyExit) {
    const ShaderReport report = analyze(R"(
void main() {
    if (uX < 0.0) {
        outColor = vec4(0.0);
        return;
    }
    outColor = vec4(uA * uB * uA, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.flops(), 1 + 6);
}

TEST(ShaderCost, CountsAPathThroughADiscard) {
    const ShaderReport report = analyze(R"(
void main() {
    if (uX < 0.0) {
        discard;
    }
    outColor = vec4(uA * uB, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.flops(), 1 + 3);
}

TEST(ShaderCost, UnrollsALoopWithAConstantTripCount) {
    const ShaderReport report = analyze(R"(
void main() {
    vec3 s = uB;
    for (int i = 0; i < 4; ++i) {
        s = s * uA + uB;  // 6 FLOPs, 4 times
    }
    outColor = vec4(s, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.flops(), 24);
    EXPECT_EQ(report.perPixel.intOps, 0);  // unrolled: no counter left
    EXPECT_FALSE(report.hasDynamicLoops);
}

TEST(ShaderCost, MultipliesARolledConstantLoopByItsTripCount) {
    // The break keeps the optimizer from unrolling; the induction variable still bounds it.
    const ShaderReport report = analyze(R"(
void main() {
    vec3 s = uB;
    for (int i = 0; i < 4; ++i) {  // i < 4 and ++i: 2 int ops
        s = s * uA + uB;           // 6
        if (s.x > uX) {            // 1
            break;
        }
    }
    outColor = vec4(s, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.flops(), 4 * (2 + 6 + 1));
    EXPECT_EQ(report.perPixel.intOps, 4 * 2);
    EXPECT_FALSE(report.hasDynamicLoops);
}

TEST(ShaderCost, CountsOneIterationOfADynamicLoop) {
    const ShaderReport report = analyze(R"(
void main() {
    vec3 d = uB;
    for (int i = 0; i < uN; ++i) {  // 2 int ops
        d += uA;                    // 3
    }
    outColor = vec4(d, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.flops(), 2 + 3);
    EXPECT_EQ(report.perPixel.intOps, 2);
    EXPECT_TRUE(report.hasDynamicLoops);
}

TEST(ShaderCost, CountsOneReciprocalPerDistinctDivisor) {
    const ShaderReport report = analyze(R"(
void main() {
    vec3 bySplat = uA / uX;   // 1 reciprocal, 3 multiplies
    vec3 byVector = uA / uB;  // 3 reciprocals, 3 multiplies
    float inverse = 1.0 / uX; // 1 reciprocal
    vec3 halved = uB / 2.0;   // a constant divisor: 3 multiplies
    outColor = vec4(bySplat + byVector + halved, inverse);  // 6 adds
}
)");
    EXPECT_EQ(report.perPixel.flops(), 3 + 3 + 3 + 6);
    EXPECT_EQ(report.perPixel.sfu, 1 + 3 + 1);
}

TEST(ShaderCost, CountsIntegerOpsAndTextureBytes) {
    const ShaderReport report = analyze(R"(
uniform highp sampler2D uTable;  // RGBA32F: a table read with texelFetch
uniform highp sampler2D uColor;  // format: RGBA16F
uniform highp usampler2D uIds;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);   // 2 conversions
    vec4 a = texelFetch(uTable, p, 0);  // 1 texel of 16 bytes
    vec4 b = texture(uColor, a.xy);     // 4 texels of 8 bytes
    uint id = texelFetch(uIds, p, 0).x; // format unknown
    outColor = b * float(id >> 2u);     // a shift, a conversion, 4 multiplies
}
)");
    EXPECT_EQ(report.perPixel.intOps, 2 + 2);
    EXPECT_EQ(report.perPixel.flops(), 4 + 4);
    EXPECT_EQ(report.perPixel.textureFetches, 3);
    EXPECT_EQ(report.perPixel.textureBytes, 16 + 4 * 8);
    EXPECT_EQ(report.perPixel.fetchesWithoutFormat, 1);
}

TEST(ShaderCost, CountsMemoryBytesReadAndWritten) {
    const ShaderCompiler compiler;
    const ShaderReport report = analyzeShader(compiler, R"(#version 310 es
precision highp float;
layout(location = 0) out vec4 outLevel;  // RGBA8: 4 bytes a pixel
uniform highp sampler2D uGeometry;  // RGBA32F: streamed, one texel a pixel
uniform highp sampler2D uWeights;   // R16F: filtered at uv, one texel a pixel from memory
uniform highp sampler2D uTable;     // RGBA16F cached: stays in the texture cache
void main() {
    vec4 g = texelFetch(uGeometry, ivec2(gl_FragCoord.xy), 0);
    float w = texture(uWeights, g.xy).r;
    outLevel = texture(uTable, vec2(w, 0.5));
}
)",
                                              "memory.frag");
    EXPECT_EQ(report.perPixel.textureFetches, 3);
    EXPECT_EQ(report.perPixel.textureBytes, 16 + 4 * 2 + 4 * 8);  // requested by the TMU
    EXPECT_EQ(report.perPixel.memoryReadBytes, 16 + 2);           // from memory
    EXPECT_EQ(report.perPixel.memoryWriteBytes, 4);
    EXPECT_EQ(report.perPixel.memoryBytes(), 22);
    EXPECT_EQ(declaredCachedTextures("uniform highp sampler2D uT;  // RGBA16F cached: h_j\n"
                                     "uniform highp sampler2D uU;  // RGBA16F: cached later\n"),
              std::set<std::string>{"uT"});
    EXPECT_EQ(declaredOutputBytes("layout(location = 0) out uvec4 outA;  // RGBA32UI\n"
                                  "layout(location = 1) out vec4 outB;\n"),
              16);
}

TEST(ShaderCost, CountsTheSineAsV3dLowersIt) {
    const ShaderReport report = analyze(R"(
void main() {
    outColor = vec4(sin(uX), cos(uX), 0.0, 1.0);
}
)");
    EXPECT_EQ(report.perPixel.sfu, 2);
    EXPECT_EQ(report.perPixel.intOps, 3 + 3);
    EXPECT_EQ(report.perPixel.flops(), (3 + 3) + (4 + 3));
}

TEST(ShaderCost, RefusesAShaderThatDoesNotCompile) {
    const ShaderCompiler compiler;
    try {
        analyzeShader(compiler,
                      std::string(kHeader) + "void main() { outColor = vec4(uMissing); }\n",
                      "bad.frag");
        FAIL() << "compiled";
    } catch (const ShaderCompileError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("bad.frag:9:"), std::string::npos) << message;
        EXPECT_NE(message.find("uMissing"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(ShaderCostTextureFormats, ReadsTheFormatCommentOfSamplerDeclarations) {
    const auto formats = declaredTextureFormats(
        "uniform highp sampler2D uTriangles; // RGBA32F: the triangle table\n"
        "layout(binding = 2) uniform mediump sampler2DArray uCodes;  // format: RGBA16F\n"
        "uniform highp usampler2D uIds;\n"
        "uniform sampler2D uCurve; // the response curve\n"
        "uniform vec3 uT; // RGBA8\n");
    EXPECT_EQ(formats, (std::map<std::string, std::string>{{"uCodes", "RGBA16F"},
                                                           {"uTriangles", "RGBA32F"}}));
    EXPECT_EQ(bytesPerTexel("R8"), 1);
    EXPECT_EQ(bytesPerTexel("RGBA16F"), 8);
    EXPECT_FALSE(bytesPerTexel("the"));
}

TEST(ShaderCostRoofline, BoundsTheFrameByTheSlowerUnit) {
    ShaderCost cost;
    cost.floatOps = 40;
    cost.textureFetches = 1;
    FrameWorkload workload;
    workload.shadedPixels = 1e6;
    workload.aluEfficiency = 1.0;
    // Pi 4: ALU 40 MFLOP / 32 GFLOPS = 1.25 ms against TMU 1 ms.
    EXPECT_NEAR(estimateFrame(cost, raspberryPi4(), workload).framesPerSecond, 800.0, 1e-9);
    // Pi 5: ALU 40 MFLOP / 122.88 GFLOPS = 0.326 ms against TMU 1 M / 3.84 G/s = 0.260 ms.
    EXPECT_NEAR(estimateFrame(cost, raspberryPi5(), workload).framesPerSecond, 3072.0, 1e-9);
    cost.textureFetches = 10;  // now the texture unit binds: 10 ms on a Pi 4
    EXPECT_NEAR(estimateFrame(cost, raspberryPi4(), workload).framesPerSecond, 100.0, 1e-9);
}

TEST(ShaderCostRoofline, BoundsTheFrameByMemoryToo) {
    ShaderCost cost;
    cost.floatOps = 40;
    cost.memoryReadBytes = 40;
    cost.memoryWriteBytes = 4;
    FrameWorkload workload;
    workload.shadedPixels = 1e6;
    workload.aluEfficiency = 1.0;
    // Pi 4: 44 MB at 5.16 GB/s = 8.53 ms, against ALU 1.25 ms.
    const FrameEstimate pi4 = estimateFrame(cost, raspberryPi4(), workload);
    EXPECT_NEAR(pi4.memoryFramesPerSecond, 5160e6 / 44e6, 1e-9);
    EXPECT_NEAR(pi4.computeFramesPerSecond, 800.0, 1e-9);
    EXPECT_NEAR(pi4.framesPerSecond, 5160e6 / 44e6, 1e-9);
    workload.memoryShare = 0.5;  // half the bandwidth: half the frame rate
    EXPECT_NEAR(estimateFrame(cost, raspberryPi4(), workload).framesPerSecond, 2580e6 / 44e6, 1e-9);
    // Pi 5: the Pi 4's STREAM/wire ratio on LPDDR4X-4267.
    EXPECT_NEAR(raspberryPi5().memoryBytes, 4267e6 * 4 * 5160e6 / 12800e6, 1e-3);
}

// The command, as a user runs it.
std::string shaderCostExecutable() {
    const char* path = std::getenv("VPE_SHADER_COST");
    return path == nullptr ? std::string() : std::string(path);
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
    std::ofstream(path) << text;
}

TEST(ShaderCostCommand, PrintsATableAndJson) {
    if (shaderCostExecutable().empty()) {
        GTEST_SKIP() << "VPE_SHADER_COST is not set (run the tests through ctest)";
    }
    testing::TemporaryFolder folder;
    writeFile(folder / "tiny.frag",
              std::string(kHeader) + "void main() { outColor = vec4(uA * uB + uA, uX); }\n");
    const testing::CommandResult result =
        testing::runCommand({shaderCostExecutable(), "--json", "--pixels", "1e6", "--efficiency",
                             "1", (folder / "tiny.frag").string()});
    ASSERT_EQ(result.exitStatus, 0) << result.err;
    EXPECT_NE(result.out.find("tiny"), std::string::npos);
    EXPECT_NE(result.out.find("FLOPs include int_ops"), std::string::npos);
    const nlohmann::json report = testing::lastJsonLine(result.out);
    ASSERT_EQ(report["shaders"].size(), 1u);
    const nlohmann::json& shader = report["shaders"][0];
    EXPECT_EQ(shader["name"], "tiny");
    EXPECT_EQ(shader["flops"], 6);
    EXPECT_EQ(shader["int_ops"], 0);
    EXPECT_EQ(shader["sfu"], 0);
    EXPECT_EQ(shader["flop_eq"], 6);
    EXPECT_EQ(shader["texture_fetches"], 0);
    EXPECT_EQ(shader["has_dynamic_loops"], false);
    EXPECT_NEAR(shader["pi4_fps"].get<double>(), 32e9 / 6e6, 1e-6);
    EXPECT_NEAR(shader["pi5_fps"].get<double>(), 122.88e9 / 6e6, 1e-6);
    EXPECT_EQ(shader["memory_bytes"], 0);  // no texture, no declared output format
}

void expectRefusal(const testing::CommandResult& result, const std::string& mention) {
    EXPECT_EQ(result.exitStatus, 2) << result.err;
    EXPECT_EQ(result.err.rfind("vpe_shader_cost: ", 0), 0u) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_NE(result.err.find(mention), std::string::npos) << result.err;
    EXPECT_TRUE(result.out.empty()) << result.out;
}

TEST(ShaderCostCommand, RefusesBadInputWithOneLine) {
    if (shaderCostExecutable().empty()) {
        GTEST_SKIP() << "VPE_SHADER_COST is not set (run the tests through ctest)";
    }
    testing::TemporaryFolder folder;
    writeFile(folder / "good.frag",
              std::string(kHeader) + "void main() { outColor = vec4(uA, uX); }\n");
    writeFile(folder / "bad.frag", std::string(kHeader) + "void main() { outColor = uNothing; }\n");
    const std::string good = (folder / "good.frag").string();
    const std::string bad = (folder / "bad.frag").string();
    const std::string missing = (folder / "missing.frag").string();

    expectRefusal(testing::runCommand({shaderCostExecutable(), good, bad}), bad + ":9:");
    expectRefusal(testing::runCommand({shaderCostExecutable(), missing}), missing);
    expectRefusal(testing::runCommand({shaderCostExecutable(), "--pixels", "-3", good}),
                  "--pixels");
    expectRefusal(testing::runCommand({shaderCostExecutable(), "--texture-format", "uX=XYZ", good}),
                  "uX=XYZ");
}

}  // namespace
}  // namespace vpe::shader_cost
