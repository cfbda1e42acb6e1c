// SPDX-License-Identifier: MIT
// One headless EGL platform shared by a test program's GLES tests; tests SKIP (not pass) with
// the platform's one-line error when this machine has no EGL display or GLES 3.1 context.
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "vpe/renderer/gles/headless_egl_platform.h"

namespace vpe::renderer::testing {

class GlesTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (platform() == nullptr && skipReason().empty()) {
            try {
                platform() = gles::createHeadlessEglPlatform();
            } catch (const gles::GraphicsError& error) {
                skipReason() = error.what();
            }
        }
    }
    void SetUp() override {
        if (platform() == nullptr) {
            GTEST_SKIP() << "no headless OpenGL ES 3.1: " << skipReason();
        }
        platform()->makeCurrent();
    }
    static std::unique_ptr<gles::GraphicsPlatform>& platform() {
        static std::unique_ptr<gles::GraphicsPlatform> instance;
        return instance;
    }
    static std::string& skipReason() {
        static std::string reason;
        return reason;
    }
};

}  // namespace vpe::renderer::testing
