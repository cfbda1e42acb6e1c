// SPDX-License-Identifier: MIT
// ShaderCompiler: GLSL ES fragment shaders to SPIR-V (glslang), then optimized as a driver would
// (SPIRV-Tools' performance passes, constant-trip loops unrolled).
//
// The shaders are OpenGL ES GLSL with loose uniforms (`uniform vec3 uT;`), which SPIR-V for
// Vulkan rejects. glslang's relaxed Vulkan rules (glslangValidator -R) accept them and gather
// the loose non-opaque uniforms into one uniform block, read with OpAccessChain + OpLoad: free
// here, as a driver takes them from the uniform stream. Samplers keep their own bindings and
// names (assigned automatically, as are the outputs' locations).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace vpe::shader_cost {

// A shader that does not compile: what() is "NAME:LINE: message" of the first error.
class ShaderCompileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class ShaderCompiler {
public:
    ShaderCompiler();  // glslang's per-process set-up; any number of compilers may coexist
    ~ShaderCompiler();
    ShaderCompiler(const ShaderCompiler&) = delete;
    ShaderCompiler& operator=(const ShaderCompiler&) = delete;

    // The SPIR-V of a fragment shader (its #version line decides the GLSL dialect; none means
    // ES 3.10), unoptimized. `name` is what error messages call the source.
    std::vector<std::uint32_t> compile(const std::string& source, const std::string& name) const;

    // The module after SPIRV-Tools' performance passes (inlining, scalar replacement, constant
    // propagation, dead-code elimination, ...), with every loop marked for unrolling first so
    // that loops with a constant trip count are unrolled, as drivers do.
    std::vector<std::uint32_t> optimize(const std::vector<std::uint32_t>& spirv,
                                        const std::string& name) const;
};

}  // namespace vpe::shader_cost
