// SPDX-License-Identifier: MIT
// PathCostAnalysis: a longest-path search over each region of the control-flow graph (the
// function, then each loop's body), with inner loops collapsed into one node each.
#include "path_cost.h"

#include <optional>
#include <stdexcept>
#include <vector>

#include "control_flow_graph.h"
#include "loop_trip_count.h"

namespace vpe::shader_cost {

namespace {

// The longest paths of one function. A region is a loop (its body, from the header to the
// back edges) or the whole function (region −1, from the entry to the returns). Inside a region
// a directly nested loop is one node: its iteration's longest path times its trip count, with
// the loop's exits as successors.
class RegionPaths {
public:
    RegionPaths(const SpirvModule& module, const ControlFlowGraph& graph,
                std::vector<ShaderCost> blockCosts)
        : module_(module),
          graph_(graph),
          blockCosts_(std::move(blockCosts)),
          loopCosts_(graph.loops().size()) {}

    ShaderCost longest(int region) {
        std::vector<std::optional<ShaderCost>> best(graph_.blockCount());
        std::vector<bool> inProgress(graph_.blockCount(), false);
        const int start = region < 0 ? 0 : loop(region).header;
        return visit(start, region, best, inProgress);
    }

    bool hasDynamicLoops() const { return hasDynamicLoops_; }

private:
    const NaturalLoop& loop(int index) const {
        return graph_.loops()[static_cast<std::size_t>(index)];
    }

    // The loop directly inside `region` that holds the block, or −1 if the block belongs to the
    // region itself.
    int childLoopHolding(int block, int region) const {
        int holder = graph_.innermostLoop(block);
        if (holder == region) {
            return -1;
        }
        while (holder >= 0 && loop(holder).parent != region) {
            holder = loop(holder).parent;
        }
        return holder;
    }

    ShaderCost loopCost(int index) {
        std::optional<ShaderCost>& cached = loopCosts_[static_cast<std::size_t>(index)];
        if (!cached) {
            const ShaderCost iteration = longest(index);
            const std::optional<std::int64_t> trips = constantTripCount(module_, graph_, index);
            if (!trips) {
                hasDynamicLoops_ = true;
            }
            cached = iteration.times(trips.value_or(1));
        }
        return *cached;
    }

    ShaderCost visit(int node, int region, std::vector<std::optional<ShaderCost>>& best,
                     std::vector<bool>& inProgress) {
        const std::size_t slot = static_cast<std::size_t>(node);
        if (best[slot]) {
            return *best[slot];
        }
        if (inProgress[slot]) {
            throw std::runtime_error("irreducible control flow at block %" +
                                     std::to_string(graph_.block(node).label));
        }
        inProgress[slot] = true;
        const int child = childLoopHolding(node, region);
        ShaderCost own;
        std::vector<int> next;
        if (child >= 0) {
            own = loopCost(child);
            next = loop(child).exits;
        } else {
            own = blockCosts_[slot];
            next = graph_.successors(node);
        }
        std::optional<ShaderCost> longestTail;
        for (const int target : next) {
            if (region >= 0 && (target == loop(region).header ||
                                !loop(region).inBody[static_cast<std::size_t>(target)])) {
                continue;  // the back edge, or an exit: this iteration's path ends here
            }
            // Entering a nested loop anywhere means entering it at its header.
            const int holder = childLoopHolding(target, region);
            const int representative = holder >= 0 ? loop(holder).header : target;
            const ShaderCost tail = visit(representative, region, best, inProgress);
            if (!longestTail || costsMore(tail, *longestTail)) {
                longestTail = tail;
            }
        }
        inProgress[slot] = false;
        best[slot] = own + longestTail.value_or(ShaderCost{});
        return *best[slot];
    }

    const SpirvModule& module_;
    const ControlFlowGraph& graph_;
    std::vector<ShaderCost> blockCosts_;
    std::vector<std::optional<ShaderCost>> loopCosts_;
    bool hasDynamicLoops_ = false;
};

}  // namespace

PathCostAnalysis::PathCostAnalysis(const SpirvModule& module, const InstructionCostModel& model)
    : module_(module), model_(model) {}

ShaderCost PathCostAnalysis::blockCost(const SpirvBlock& block) {
    ShaderCost cost;
    for (const SpirvInstruction& instruction : block.instructions) {
        if (instruction.opcode == spv::OpFunctionCall) {
            cost += longestPath(instruction.operands.at(0));
            continue;
        }
        if (!model_.knows(instruction)) {
            ++uncounted_[instruction.opcode];
        }
        cost += model_.cost(instruction);
    }
    return cost;
}

ShaderCost PathCostAnalysis::longestPath(std::uint32_t functionId) {
    if (const auto found = functionCosts_.find(functionId); found != functionCosts_.end()) {
        return found->second;
    }
    const SpirvFunction* function = module_.function(functionId);
    if (function == nullptr) {
        throw std::runtime_error("call of %" + std::to_string(functionId) +
                                 ", which is not a function of the module");
    }
    if (!functionsInProgress_.insert(functionId).second) {
        throw std::runtime_error("recursive call of %" + std::to_string(functionId));
    }
    const ControlFlowGraph graph(*function);
    std::vector<ShaderCost> blockCosts;
    blockCosts.reserve(graph.blockCount());
    for (std::size_t b = 0; b < graph.blockCount(); ++b) {
        blockCosts.push_back(blockCost(graph.block(static_cast<int>(b))));
    }
    RegionPaths paths(module_, graph, std::move(blockCosts));
    const ShaderCost cost = paths.longest(-1);
    hasDynamicLoops_ = hasDynamicLoops_ || paths.hasDynamicLoops();
    functionsInProgress_.erase(functionId);
    functionCosts_[functionId] = cost;
    return cost;
}

}  // namespace vpe::shader_cost
