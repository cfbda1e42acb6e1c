// SPDX-License-Identifier: MIT
// analyzeShader: compile, optimize, read the module, cost the fragment entry point's paths.
#include "shader_analysis.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "instruction_cost.h"
#include "path_cost.h"
#include "spirv_module.h"
#include "texture_formats.h"

namespace vpe::shader_cost {

ShaderReport analyzeShader(const ShaderCompiler& compiler, const std::string& source,
                           const std::string& name,
                           const std::map<std::string, std::string>& textureFormats) {
    ShaderReport report;
    report.name = name;
    report.textureFormats = declaredTextureFormats(source);
    for (const auto& [sampler, format] : textureFormats) {
        report.textureFormats[sampler] = format;
    }
    std::map<std::string, int> texelBytes;
    for (const auto& [sampler, format] : report.textureFormats) {
        if (const std::optional<int> bytes = bytesPerTexel(format)) {
            texelBytes[sampler] = *bytes;
        }
    }

    report.spirv = compiler.optimize(compiler.compile(source, name), name);
    try {
        const SpirvModule module(report.spirv);
        const InstructionCostModel model(module, std::move(texelBytes),
                                         declaredCachedTextures(source));
        PathCostAnalysis paths(module, model);
        report.perPixel = paths.longestPath(module.fragmentEntryPoint());
        report.perPixel.memoryWriteBytes = declaredOutputBytes(source);
        report.hasDynamicLoops = paths.hasDynamicLoops();
        report.uncountedOpcodes = paths.uncountedOpcodes();
    } catch (const std::runtime_error& error) {
        throw std::runtime_error(name + ": " + error.what());
    }
    return report;
}

ShaderReport analyzeShaderFile(const ShaderCompiler& compiler, const std::filesystem::path& path,
                               const std::map<std::string, std::string>& textureFormats) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) {
        throw ShaderCompileError(path.string() + ": is a directory, not a shader");
    }
    std::ifstream stream(path, std::ios::binary);
    if (!stream) {
        throw ShaderCompileError(path.string() + ": cannot read (" + std::strerror(errno) + ")");
    }
    std::ostringstream text;
    text << stream.rdbuf();
    ShaderReport report = analyzeShader(compiler, text.str(), path.string(), textureFormats);
    report.name = path.stem().string();
    return report;
}

}  // namespace vpe::shader_cost
