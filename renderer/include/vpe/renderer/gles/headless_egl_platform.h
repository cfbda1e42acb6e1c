// SPDX-License-Identifier: MIT
// HeadlessEglPlatform: an OpenGL ES 3.1 context on EGL's Mesa surfaceless platform
// (EGL_MESA_platform_surfaceless, no window, no /dev/dri needed: llvmpipe) rendering into
// framebuffer objects that are read back. Filament's PlatformEGLHeadless.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

struct HeadlessEglOptions {
    // The context version requested (GLES 3.1: the Pi 4/5's v3d limit; nothing beyond).
    int majorVersion = 3;
    int minorVersion = 1;
    // Extensions required on top of the platform's own (EGL client extensions are those of
    // EGL_NO_DISPLAY; display extensions those of the display). For tests and devices that
    // need more.
    std::vector<std::string> extraClientExtensions;
    std::vector<std::string> extraDisplayExtensions;
};

// Creates the display, the context and makes it current. Throws GraphicsError with one line
// naming what is missing: "EGL: client extension EGL_MESA_platform_surfaceless is missing",
// "EGL: no surfaceless display (eglInitialize: EGL_NOT_INITIALIZED)", "EGL: cannot create an
// OpenGL ES 3.1 context: EGL_BAD_MATCH".
std::unique_ptr<GraphicsPlatform> createHeadlessEglPlatform(const HeadlessEglOptions& options = {});

}  // namespace vpe::renderer::gles
