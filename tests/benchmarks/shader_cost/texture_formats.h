// SPDX-License-Identifier: MIT
// Texture formats of a shader's samplers: the comment convention, and bytes per texel.
//
// Convention: a sampler uniform's format is the first word of a comment on its declaration's
// line, optionally after "format:", when it names a sized GLES internal format:
//   uniform highp sampler2D uTriangles; // RGBA32F: the triangle table
//   uniform highp sampler2DArray uRegion0;  // format: RGBA16F
// The generated shaders already write some formats that way; others can be given on the
// command line (vpe_shader_cost --texture-format uRegion0=RGBA16F).
#pragma once

#include <map>
#include <optional>
#include <string>

namespace vpe::shader_cost {

// Sampler name → format name, from the declarations' comments in GLSL source.
std::map<std::string, std::string> declaredTextureFormats(const std::string& source);

// Bytes of one texel of a sized internal format ("RGBA16F" → 8), or nullopt if unknown.
std::optional<int> bytesPerTexel(const std::string& format);

}  // namespace vpe::shader_cost
