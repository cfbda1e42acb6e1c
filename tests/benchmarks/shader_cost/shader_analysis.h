// SPDX-License-Identifier: MIT
// analyzeShader: GLSL source → optimized SPIR-V → the cost of its most expensive path per pixel.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "shader_compiler.h"
#include "shader_cost.h"

namespace vpe::shader_cost {

struct ShaderReport {
    std::string name;
    ShaderCost perPixel;
    bool hasDynamicLoops = false;
    std::map<std::uint32_t, std::int64_t> uncountedOpcodes;  // SPIR-V opcode → instructions
    std::map<std::string, std::string> textureFormats;       // sampler → format used for bytes
    std::vector<std::uint32_t> spirv;  // the optimized module that was counted
};

// `textureFormats` (sampler → format) adds to and overrides the formats the source declares in
// comments (texture_formats.h). Throws ShaderCompileError naming `name` when the source does not
// compile, std::runtime_error when the SPIR-V cannot be analysed.
ShaderReport analyzeShader(const ShaderCompiler& compiler, const std::string& source,
                           const std::string& name,
                           const std::map<std::string, std::string>& textureFormats = {});

// The same for a file; the report is named after the file's stem. A file that cannot be read
// throws ShaderCompileError naming it.
ShaderReport analyzeShaderFile(const ShaderCompiler& compiler, const std::filesystem::path& path,
                               const std::map<std::string, std::string>& textureFormats = {});

}  // namespace vpe::shader_cost
