// SPDX-License-Identifier: MIT
// ControlFlowGraph: back edges from a depth-first search, natural loops from the back edges.
#include "control_flow_graph.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace vpe::shader_cost {

ControlFlowGraph::ControlFlowGraph(const SpirvFunction& function) {
    if (function.blocks.empty()) {
        throw std::runtime_error("function %" + std::to_string(function.id) + " has no blocks");
    }
    for (const SpirvBlock& block : function.blocks) {
        indices_[block.label] = static_cast<int>(blocks_.size());
        blocks_.push_back(&block);
    }
    successors_.resize(blocks_.size());
    predecessors_.resize(blocks_.size());
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
        for (const std::uint32_t label : blocks_[b]->successors) {
            const int target = indexOf(label);
            // A switch may name a target twice; one edge is enough.
            if (std::find(successors_[b].begin(), successors_[b].end(), target) ==
                successors_[b].end()) {
                successors_[b].push_back(target);
                predecessors_[static_cast<std::size_t>(target)].push_back(static_cast<int>(b));
            }
        }
    }
    findLoops();
}

int ControlFlowGraph::indexOf(std::uint32_t label) const {
    const auto found = indices_.find(label);
    if (found == indices_.end()) {
        throw std::runtime_error("branch to %" + std::to_string(label) +
                                 ", which is not a block of the function");
    }
    return found->second;
}

void ControlFlowGraph::findLoops() {
    const std::size_t count = blocks_.size();
    // Iterative depth-first search from the entry: an edge to a block still on the stack is a
    // back edge, and its target a loop header.
    enum class Mark { Unseen, OnStack, Done };
    std::vector<Mark> marks(count, Mark::Unseen);
    std::vector<std::pair<int, std::size_t>> stack{{0, 0}};
    marks[0] = Mark::OnStack;
    std::vector<std::pair<int, int>> backEdges;  // (latch, header)
    while (!stack.empty()) {
        auto& [node, next] = stack.back();
        const std::vector<int>& out = successors_[static_cast<std::size_t>(node)];
        if (next == out.size()) {
            marks[static_cast<std::size_t>(node)] = Mark::Done;
            stack.pop_back();
            continue;
        }
        const int target = out[next++];
        const int source = node;  // `node` dangles once the stack grows
        if (marks[static_cast<std::size_t>(target)] == Mark::OnStack) {
            backEdges.emplace_back(source, target);
        } else if (marks[static_cast<std::size_t>(target)] == Mark::Unseen) {
            marks[static_cast<std::size_t>(target)] = Mark::OnStack;
            stack.emplace_back(target, 0);
        }
    }

    // One natural loop per header: the header and every block that reaches a latch without
    // passing through the header.
    std::unordered_map<int, std::size_t> loopOfHeader;
    for (const auto& [latch, header] : backEdges) {
        auto [found, inserted] = loopOfHeader.try_emplace(header, loops_.size());
        if (inserted) {
            NaturalLoop loop;
            loop.header = header;
            loop.inBody.assign(count, false);
            loop.inBody[static_cast<std::size_t>(header)] = true;
            loops_.push_back(std::move(loop));
        }
        NaturalLoop& loop = loops_[found->second];
        loop.latches.push_back(latch);
        std::vector<int> work{latch};
        while (!work.empty()) {
            const int node = work.back();
            work.pop_back();
            if (loop.inBody[static_cast<std::size_t>(node)]) {
                continue;
            }
            loop.inBody[static_cast<std::size_t>(node)] = true;
            for (const int predecessor : predecessors_[static_cast<std::size_t>(node)]) {
                if (marks[static_cast<std::size_t>(predecessor)] != Mark::Unseen) {
                    work.push_back(predecessor);
                }
            }
        }
    }
    for (NaturalLoop& loop : loops_) {
        loop.size =
            static_cast<std::size_t>(std::count(loop.inBody.begin(), loop.inBody.end(), true));
        for (std::size_t b = 0; b < count; ++b) {
            if (!loop.inBody[b]) {
                continue;
            }
            for (const int target : successors_[b]) {
                if (!loop.inBody[static_cast<std::size_t>(target)] &&
                    std::find(loop.exits.begin(), loop.exits.end(), target) == loop.exits.end()) {
                    loop.exits.push_back(target);
                }
            }
        }
    }
    // Nesting: the innermost loop of a block is the smallest body holding it.
    const auto innermostHolding = [&](int block, int excluded) {
        int best = -1;
        for (std::size_t l = 0; l < loops_.size(); ++l) {
            if (static_cast<int>(l) != excluded &&
                loops_[l].inBody[static_cast<std::size_t>(block)] &&
                (best < 0 || loops_[l].size < loops_[static_cast<std::size_t>(best)].size)) {
                best = static_cast<int>(l);
            }
        }
        return best;
    };
    for (std::size_t l = 0; l < loops_.size(); ++l) {
        loops_[l].parent = innermostHolding(loops_[l].header, static_cast<int>(l));
    }
    innermost_.resize(count);
    for (std::size_t b = 0; b < count; ++b) {
        innermost_[b] = innermostHolding(static_cast<int>(b), -1);
    }
}

}  // namespace vpe::shader_cost
