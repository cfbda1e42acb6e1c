// SPDX-License-Identifier: MIT
// KmsPlatform without a display (this machine, CI): a clean one-line GraphicsError naming the
// node. With a KMS device present the absent-node cases still run; nothing is modeset.
#include "vpe/renderer/gles/kms_platform.h"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace vpe::renderer::gles {
namespace {

std::string errorOf(const KmsOptions& options) {
    try {
        createKmsPlatform(options);
    } catch (const GraphicsError& error) {
        return error.what();
    }
    return "(no error)";
}

TEST(KmsPlatformTest, AbsentDefaultNodeIsAOneLineError) {
    if (std::filesystem::exists("/dev/dri/card0")) {
        GTEST_SKIP() << "/dev/dri/card0 exists on this machine";
    }
    EXPECT_EQ(errorOf({}), "/dev/dri/card0: no such device (KMS display unavailable)");
}

TEST(KmsPlatformTest, AbsentNodeIsNamed) {
    KmsOptions options;
    options.device = "/nonexistent/dri/card7";
    EXPECT_EQ(errorOf(options), "/nonexistent/dri/card7: no such device (KMS display unavailable)");
}

TEST(KmsPlatformTest, ANodeThatIsNotKmsIsRefused) {
    KmsOptions options;
    options.device = "/dev/null";
    const std::string error = errorOf(options);
    EXPECT_EQ(error.rfind("/dev/null: not a KMS device (drmModeGetResources: ", 0), 0u) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
}

TEST(KmsPlatformTest, AutoWithoutDevicesIsAOneLineError) {
    if (std::filesystem::exists("/dev/dri")) {
        GTEST_SKIP() << "/dev/dri exists on this machine";
    }
    KmsOptions options;
    options.device = "auto";
    EXPECT_EQ(errorOf(options),
              "/dev/dri: no KMS device with a usable connector (KMS display unavailable)");
}

}  // namespace
}  // namespace vpe::renderer::gles
