// SPDX-License-Identifier: MIT
// PathCostAnalysis: the cost of the most expensive path through a function's control flow.
//
// The rule: a pixel runs one path from the entry to a return (or discard). At every branch the
// analysis takes the more expensive side (ALU issue time, then texture fetches), so an early
// exit such as "if (id == 0u) { ...; return; }" only counts if it costs more than shading;
// the result is an upper bound for a pixel that takes the branches it likes least. Loops count
// their most expensive iteration times the trip count when the loop's induction variable makes
// it constant (the optimizer has already unrolled what it could); otherwise one iteration, and
// the shader is reported as having dynamic loops.
#pragma once

#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "instruction_cost.h"
#include "shader_cost.h"
#include "spirv_module.h"

namespace vpe::shader_cost {

class PathCostAnalysis {
public:
    PathCostAnalysis(const SpirvModule& module, const InstructionCostModel& model);

    // The most expensive path through the function, callees included. Throws
    // std::runtime_error on control flow it cannot order (irreducible, recursive).
    ShaderCost longestPath(std::uint32_t function);

    // Whether a loop whose trip count is not constant was met (counted once).
    bool hasDynamicLoops() const { return hasDynamicLoops_; }
    // Opcodes with no counting rule (counted free), with the number of instructions met.
    const std::map<std::uint32_t, std::int64_t>& uncountedOpcodes() const { return uncounted_; }

    // The cost of a block's own instructions, callees' paths included.
    ShaderCost blockCost(const SpirvBlock& block);

private:
    const SpirvModule& module_;
    const InstructionCostModel& model_;
    std::unordered_map<std::uint32_t, ShaderCost> functionCosts_;
    std::unordered_set<std::uint32_t> functionsInProgress_;
    std::map<std::uint32_t, std::int64_t> uncounted_;
    bool hasDynamicLoops_ = false;
};

}  // namespace vpe::shader_cost
