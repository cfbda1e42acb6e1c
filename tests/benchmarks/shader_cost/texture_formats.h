// SPDX-License-Identifier: MIT
// Texture formats of a shader's samplers: the comment convention, and bytes per texel.
//
// Convention: a sampler uniform's format is the first word of a comment on its declaration's
// line, optionally after "format:", when it names a sized GLES internal format:
//   uniform highp sampler2D uTriangles; // RGBA32F: the triangle table
//   uniform highp sampler2DArray uRegion0;  // format: RGBA16F
// The generated shaders already write some formats that way; others can be given on the
// command line (vpe_shader_cost --texture-format uRegion0=RGBA16F). A colour output's comment
// names its attachment's format the same way; the word "cached" after a sampler's format marks
// a table that stays in the texture cache.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

namespace vpe::shader_cost {

// Sampler name → format name, from the declarations' comments in GLSL source.
std::map<std::string, std::string> declaredTextureFormats(const std::string& source);

// The samplers declared cached: the word "cached" right after the format,
//   uniform highp sampler2D uThetaTable;  // RGBA16F cached: 8 KB, stays in the TMU's cache
// (a table small enough to be read from memory once a frame, not once a pixel).
std::set<std::string> declaredCachedTextures(const std::string& source);

// Bytes a pixel writes: the colour outputs whose declaration's comment names a format,
//   layout(location = 0) out vec4 outLevel;  // RGBA8: the drive levels
std::int64_t declaredOutputBytes(const std::string& source);

// Bytes of one texel of a sized internal format ("RGBA16F" → 8), or nullopt if unknown.
std::optional<int> bytesPerTexel(const std::string& format);

}  // namespace vpe::shader_cost
