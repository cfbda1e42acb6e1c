// SPDX-License-Identifier: MIT
// InstructionCostModel: what one SPIR-V instruction costs per pixel (docs/shader-cost.md).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "shader_cost.h"
#include "spirv_module.h"

namespace vpe::shader_cost {

class InstructionCostModel {
public:
    // texelBytes: sampler uniform name → bytes per texel, for the samplers whose format is known;
    // cached: the samplers whose texture stays in the TMU's cache (no memory traffic).
    InstructionCostModel(const SpirvModule& module, std::map<std::string, int> texelBytes,
                         std::set<std::string> cached = {});

    // The cost of one instruction. A function call costs nothing here: the path analysis adds
    // the callee's path.
    ShaderCost cost(const SpirvInstruction& instruction) const;

    // Whether the model has a rule for the instruction (free ones included). Instructions
    // without one are counted as free; the report lists them.
    bool knows(const SpirvInstruction& instruction) const;

    // The name of the sampler uniform an image operand comes from, or "" if not traceable.
    std::string samplerName(std::uint32_t id) const;

private:
    // The cost, or nullopt when no rule covers the instruction.
    std::optional<ShaderCost> rule(const SpirvInstruction& instruction) const;
    std::optional<ShaderCost> extendedCost(const SpirvInstruction& instruction) const;
    ShaderCost textureCost(const SpirvInstruction& instruction) const;
    ShaderCost divisionCost(const SpirvInstruction& instruction) const;
    bool negationIsFolded(const SpirvInstruction& instruction) const;

    const SpirvModule& module_;
    std::map<std::string, int> texelBytes_;
    std::set<std::string> cached_;
};

}  // namespace vpe::shader_cost
