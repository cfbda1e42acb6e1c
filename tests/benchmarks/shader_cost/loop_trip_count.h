// SPDX-License-Identifier: MIT
// Constant trip counts of the loops the optimizer left rolled, from their induction variables.
#pragma once

#include <cstdint>
#include <optional>

#include "control_flow_graph.h"
#include "spirv_module.h"

namespace vpe::shader_cost {

// How many times the loop's body runs at most, when that is a constant: an exit test comparing
// an integer induction variable (a header OpPhi of a constant start and itself ± a constant
// step) or its next value with a constant; other exits (break, return) only end it earlier.
// A loop whose back edges are all branches on a constant false runs once. nullopt otherwise.
std::optional<std::int64_t> constantTripCount(const SpirvModule& module,
                                              const ControlFlowGraph& graph, int loop);

}  // namespace vpe::shader_cost
