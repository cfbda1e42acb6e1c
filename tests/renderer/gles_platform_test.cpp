// SPDX-License-Identifier: MIT
// Clear, one-line errors: missing EGL extensions, an unavailable context version, a shader
// that does not compile, textures and targets beyond the limits.
#include <iostream>
#include <string>

#include <GLES3/gl31.h>
#include <gtest/gtest.h>

#include "vpe/renderer/gles/gles_frame_renderer.h"

#include "gl_program.h"
#include "gles_test_bundle.h"
#include "gles_test_platform.h"

namespace vpe::renderer::testing {
namespace {

using gles::GraphicsError;

bool oneLine(const std::string& text) {
    return !text.empty() && text.find('\n') == std::string::npos;
}

// The message of the GraphicsError that action throws; a failure (noThrow) and "" when it
// throws none.
template <typename Action>
std::string graphicsErrorOf(Action&& action,
                            const std::string& noThrow = "expected GraphicsError") {
    try {
        action();
    } catch (const GraphicsError& error) {
        return error.what();
    }
    ADD_FAILURE() << noThrow;
    return "";
}

class GlesPlatformTest : public GlesTest {};

// These run whether or not EGL works here: the platform must fail cleanly, never crash.
TEST(GlesPlatformErrors, MissingClientExtensionIsAClearError) {
    gles::HeadlessEglOptions options;
    options.extraClientExtensions = {"EGL_VPE_no_such_extension"};
    const std::string message = graphicsErrorOf([&] { gles::createHeadlessEglPlatform(options); });
    EXPECT_TRUE(oneLine(message)) << message;
    EXPECT_EQ(message.rfind("EGL: ", 0), 0u) << message;
    EXPECT_NE(message.find("is missing"), std::string::npos) << message;
}

TEST_F(GlesPlatformTest, MissingDisplayExtensionIsAClearError) {
    gles::HeadlessEglOptions options;
    options.extraDisplayExtensions = {"EGL_VPE_no_such_extension"};
    const std::string message = graphicsErrorOf([&] { gles::createHeadlessEglPlatform(options); });
    EXPECT_EQ(message, "EGL: display extension EGL_VPE_no_such_extension is missing");
}

TEST_F(GlesPlatformTest, UnavailableContextVersionIsAClearError) {
    gles::HeadlessEglOptions options;
    options.majorVersion = 9;
    options.minorVersion = 9;
    const std::string message = graphicsErrorOf([&] { gles::createHeadlessEglPlatform(options); });
    EXPECT_TRUE(oneLine(message)) << message;
    EXPECT_EQ(message.rfind("EGL: cannot create an OpenGL ES 9.9 context: ", 0), 0u) << message;
    platform()->makeCurrent();
}

TEST_F(GlesPlatformTest, DescribesTheContext) {
    const std::string description = platform()->description();
    EXPECT_NE(description.find("OpenGL ES 3."), std::string::npos) << description;
    std::cout << description << "\n";
}

TEST_F(GlesPlatformTest, BrokenShaderNamesTheShaderAndTheLogsFirstLine) {
    const std::string source =
        "#version 310 es\nprecision highp float;\nout vec4 colour;\n"
        "void main() {\n    colour = vpe_undefined_function(1.0);\n}\n";
    const std::string message =
        graphicsErrorOf([&] { gles::compileShader(GL_FRAGMENT_SHADER, "broken.frag", source); });
    EXPECT_TRUE(oneLine(message)) << message;
    EXPECT_EQ(message.rfind("shader 'broken.frag' does not compile: ", 0), 0u) << message;
    EXPECT_NE(message.find("vpe_undefined_function"), std::string::npos) << message;
}

TEST_F(GlesPlatformTest, ShaderBeyondEs31IsRefused) {
    // Nothing beyond ES 3.1, even where the driver offers 3.2.
    const std::string message = graphicsErrorOf(
        [&] {
            gles::compileShader(GL_FRAGMENT_SHADER, "es32.frag",
                                "#version 320 es\nprecision highp float;\nout vec4 c;\n"
                                "void main() { c = vec4(1.0); }\n");
        },
        "a 3.1 context compiled a #version 320 es shader");
    EXPECT_EQ(message,
              "shader 'es32.frag' must start with '#version 310 es' (OpenGL ES 3.1 at "
              "most), not '#version 320 es'");
}

TEST_F(GlesPlatformTest, OversizeTexturesAreRefused) {
    MappedTestBundle bundle;  // 32 x 24 textures, 160 x 120 projector
    gles::GlesRendererOptions options;
    options.maxTextureSize = 200;
    EXPECT_NO_THROW(gles::GlesFrameRenderer(bundle.view(), options));
    options.maxTextureSize = 16;
    const std::string message =
        graphicsErrorOf([&] { gles::GlesFrameRenderer renderer(bundle.view(), options); });
    EXPECT_TRUE(oneLine(message)) << message;
    EXPECT_NE(message.find("is larger than the texture limit 16"), std::string::npos) << message;
    GlesBundleSpec spec;  // textures larger than the projector
    spec.textureWidth = 64;
    spec.projectorWidth = 40;
    spec.projectorHeight = 30;
    MappedTestBundle wide(spec);
    options.maxTextureSize = 48;
    const std::string wideMessage =
        graphicsErrorOf([&] { gles::GlesFrameRenderer renderer(wide.view(), options); });
    EXPECT_TRUE(oneLine(wideMessage)) << wideMessage;
    EXPECT_NE(wideMessage.find("textures 64x24 are larger than the limit 48"), std::string::npos)
        << wideMessage;
}

TEST_F(GlesPlatformTest, OversizeRenderTargetIsRefused) {
    const std::string message =
        graphicsErrorOf([&] { platform()->createRenderTarget(1 << 20, 16); });
    EXPECT_NE(message.find("GL_MAX_RENDERBUFFER_SIZE"), std::string::npos) << message;
}

TEST_F(GlesPlatformTest, TargetOfAnotherSizeIsRefused) {
    MappedTestBundle bundle;
    gles::GlesFrameRenderer renderer(bundle.view());
    auto target = platform()->createRenderTarget(64, 64);
    EXPECT_THROW(renderer.render(*target, {}), GraphicsError);
}

}  // namespace
}  // namespace vpe::renderer::testing
