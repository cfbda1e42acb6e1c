// SPDX-License-Identifier: MIT
// ControlFlowGraph: a function's blocks, their edges, and its natural loops and their nesting.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "spirv_module.h"

namespace vpe::shader_cost {

struct NaturalLoop {
    int header = 0;
    std::vector<int> latches;  // blocks with a back edge to the header
    std::vector<bool> inBody;  // per block: part of the loop (header included)
    std::vector<int> exits;    // blocks outside the loop that its blocks branch to
    int parent = -1;           // the innermost enclosing loop, or -1
    std::size_t size = 0;      // blocks in the body
};

class ControlFlowGraph {
public:
    // Blocks are numbered in the function's order (the entry is 0). Throws std::runtime_error
    // when a branch names a block the function lacks.
    explicit ControlFlowGraph(const SpirvFunction& function);

    std::size_t blockCount() const { return blocks_.size(); }
    const SpirvBlock& block(int index) const { return *blocks_[static_cast<std::size_t>(index)]; }
    const std::vector<int>& successors(int index) const {
        return successors_[static_cast<std::size_t>(index)];
    }
    const std::vector<NaturalLoop>& loops() const { return loops_; }
    // The innermost loop holding the block, or -1.
    int innermostLoop(int index) const { return innermost_[static_cast<std::size_t>(index)]; }
    int indexOf(std::uint32_t label) const;

private:
    void findLoops();

    std::vector<const SpirvBlock*> blocks_;
    std::unordered_map<std::uint32_t, int> indices_;
    std::vector<std::vector<int>> successors_;
    std::vector<std::vector<int>> predecessors_;
    std::vector<NaturalLoop> loops_;
    std::vector<int> innermost_;
};

}  // namespace vpe::shader_cost
