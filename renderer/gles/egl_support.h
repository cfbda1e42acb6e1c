// SPDX-License-Identifier: MIT
// What every EGL platform (headless, KMS) needs: readable EGL errors and extension lookup.
#pragma once

#include <string>

#include <EGL/egl.h>

namespace vpe::renderer::gles {

// "EGL_BAD_MATCH", or "EGL error 0x…" for codes without a name.
std::string eglErrorName(EGLint error);

// Whether the space-separated extension `list` (may be null) names `name` exactly.
bool hasEglExtension(const char* list, const std::string& name);

}  // namespace vpe::renderer::gles
