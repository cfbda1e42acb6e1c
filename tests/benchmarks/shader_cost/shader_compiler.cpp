// SPDX-License-Identifier: MIT
// ShaderCompiler: glslang's C++ API (TShader, TProgram, GlslangToSpv) and spvtools::Optimizer.
#include "shader_compiler.h"

#include <sstream>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <glslang/SPIRV/spirv.hpp>
#include <spirv-tools/libspirv.h>
#include <spirv-tools/optimizer.hpp>

namespace vpe::shader_cost {

namespace {

constexpr std::size_t kHeaderWords = 5;

// The first "ERROR: ..." line of a glslang log, without the prefix; else the first line.
std::string firstLogError(const std::string& log) {
    std::istringstream lines(log);
    std::string line;
    std::string first;
    while (std::getline(lines, line)) {
        if (line.rfind("ERROR: ", 0) == 0) {
            return line.substr(7);
        }
        if (first.empty() && !line.empty()) {
            first = line;
        }
    }
    return first.empty() ? "compilation failed" : first;
}

// The first error, naming the source as "NAME:LINE: ..." (glslang's own form) or "NAME: ...".
std::string firstError(const std::string& log, const std::string& name) {
    const std::string error = firstLogError(log);
    return error.rfind(name + ":", 0) == 0 ? error : name + ": " + error;
}

// Marks every loop Unroll (and not DontUnroll): SPIRV-Tools' loop unroller only touches loops
// that ask for it, where a GPU driver unrolls constant-trip loops on its own.
std::vector<std::uint32_t> withLoopsMarkedForUnrolling(std::vector<std::uint32_t> spirv) {
    std::size_t at = kHeaderWords;
    while (at < spirv.size()) {
        const std::uint32_t wordCount = spirv[at] >> 16;
        if (wordCount == 0) {
            break;
        }
        if ((spirv[at] & 0xffffu) == spv::OpLoopMerge && wordCount >= 4 && at + 3 < spirv.size()) {
            spirv[at + 3] = (spirv[at + 3] & ~std::uint32_t{spv::LoopControlDontUnrollMask}) |
                            spv::LoopControlUnrollMask;
        }
        at += wordCount;
    }
    return spirv;
}

}  // namespace

ShaderCompiler::ShaderCompiler() {
    glslang::InitializeProcess();
}

ShaderCompiler::~ShaderCompiler() {
    glslang::FinalizeProcess();
}

std::vector<std::uint32_t> ShaderCompiler::compile(const std::string& source,
                                                   const std::string& name) const {
    glslang::TShader shader(EShLangFragment);
    const char* text = source.c_str();
    const int length = static_cast<int>(source.size());
    const char* names[] = {name.c_str()};
    shader.setStringsWithLengthsAndNames(&text, &length, names, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangFragment, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_0);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
    shader.setEnvInputVulkanRulesRelaxed();
    shader.setAutoMapBindings(true);
    shader.setAutoMapLocations(true);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 310, EEsProfile, false, false, messages)) {
        throw ShaderCompileError(firstError(shader.getInfoLog(), name));
    }
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages) || !program.mapIO()) {
        throw ShaderCompileError(firstError(program.getInfoLog(), name));
    }
    std::vector<std::uint32_t> spirv;
    spv::SpvBuildLogger logger;
    glslang::SpvOptions options;
    options.disableOptimizer = true;  // optimize() runs the passes, with loops marked first
    glslang::GlslangToSpv(*program.getIntermediate(EShLangFragment), spirv, &logger, &options);
    const std::string log = logger.getAllMessages();
    if (log.find("error") != std::string::npos) {
        throw ShaderCompileError(firstError(log, name));
    }
    return spirv;
}

std::vector<std::uint32_t> ShaderCompiler::optimize(const std::vector<std::uint32_t>& spirv,
                                                    const std::string& name) const {
    spvtools::Optimizer optimizer(SPV_ENV_VULKAN_1_0);
    std::string firstMessage;
    optimizer.SetMessageConsumer([&firstMessage](spv_message_level_t level, const char*,
                                                 const spv_position_t&, const char* message) {
        if (level <= SPV_MSG_ERROR && firstMessage.empty()) {
            firstMessage = message;
        }
    });
    optimizer.RegisterPerformancePasses();
    std::vector<std::uint32_t> optimized;
    const std::vector<std::uint32_t> marked = withLoopsMarkedForUnrolling(spirv);
    if (!optimizer.Run(marked.data(), marked.size(), &optimized)) {
        throw ShaderCompileError(
            name + ": SPIR-V optimizer: " + (firstMessage.empty() ? "failed" : firstMessage));
    }
    return optimized;
}

}  // namespace vpe::shader_cost
