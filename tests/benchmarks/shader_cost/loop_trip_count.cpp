// SPDX-License-Identifier: MIT
// Loop trip counts: the induction pattern glslang emits for `for (int i = A; i < B; i += C)`,
// run step by step (no closed form to get wrong for <=, !=, unsigned or negative steps).
#include "loop_trip_count.h"

#include <algorithm>

namespace vpe::shader_cost {

namespace {

constexpr std::int64_t kMaximumTrips = std::int64_t{1} << 24;

struct Induction {
    std::int64_t start = 0;
    std::int64_t step = 0;
    bool comparesNextValue = false;  // the test reads i ± step, not i
};

// The header phi's start (from outside the loop) and step (from inside), if `value` is the phi
// (or its increment) of an induction variable of the loop.
std::optional<Induction> inductionOf(const SpirvModule& module, const ControlFlowGraph& graph,
                                     const NaturalLoop& loop, std::uint32_t value) {
    const SpirvInstruction* definition = module.definition(value);
    if (definition == nullptr) {
        return std::nullopt;
    }
    bool comparesNext = false;
    std::uint32_t phiId = value;
    if (definition->opcode == spv::OpIAdd || definition->opcode == spv::OpISub) {
        comparesNext = true;
        const std::uint32_t a = definition->operands.at(0);
        const std::uint32_t b = definition->operands.at(1);
        phiId = module.integerConstant(b) ? a : b;
        definition = module.definition(phiId);
        if (definition == nullptr) {
            return std::nullopt;
        }
    }
    if (definition->opcode != spv::OpPhi || definition->operands.size() != 4) {
        return std::nullopt;
    }
    const SpirvBlock& header = graph.block(loop.header);
    const bool inHeader = std::any_of(
        header.instructions.begin(), header.instructions.end(),
        [&](const SpirvInstruction& instruction) { return instruction.result == phiId; });
    if (!inHeader) {
        return std::nullopt;
    }
    Induction induction;
    induction.comparesNextValue = comparesNext;
    std::optional<std::int64_t> start;
    std::optional<std::int64_t> step;
    for (std::size_t pair = 0; pair < 4; pair += 2) {
        const std::uint32_t incoming = definition->operands[pair];
        const bool fromInside =
            loop.inBody[static_cast<std::size_t>(graph.indexOf(definition->operands[pair + 1]))];
        if (!fromInside) {
            start = module.integerConstant(incoming);
            continue;
        }
        // The update: phi + constant, constant + phi, or phi − constant.
        const SpirvInstruction* update = module.definition(incoming);
        if (update == nullptr || (update->opcode != spv::OpIAdd && update->opcode != spv::OpISub)) {
            return std::nullopt;
        }
        const std::uint32_t a = update->operands.at(0);
        const std::uint32_t b = update->operands.at(1);
        if (a == phiId && module.integerConstant(b)) {
            step = update->opcode == spv::OpIAdd ? *module.integerConstant(b)
                                                 : -*module.integerConstant(b);
        } else if (b == phiId && update->opcode == spv::OpIAdd && module.integerConstant(a)) {
            step = *module.integerConstant(a);
        } else {
            return std::nullopt;
        }
        if (comparesNext && incoming != value) {
            return std::nullopt;  // the test reads another increment than the loop's
        }
    }
    if (!start || !step || *step == 0) {
        return std::nullopt;
    }
    induction.start = *start;
    induction.step = *step;
    return induction;
}

// Evaluates an integer comparison; nullopt for other opcodes.
std::optional<bool> compare(spv::Op opcode, std::int64_t a, std::int64_t b) {
    switch (opcode) {
        case spv::OpSLessThan:
        case spv::OpULessThan:
            return a < b;
        case spv::OpSLessThanEqual:
        case spv::OpULessThanEqual:
            return a <= b;
        case spv::OpSGreaterThan:
        case spv::OpUGreaterThan:
            return a > b;
        case spv::OpSGreaterThanEqual:
        case spv::OpUGreaterThanEqual:
            return a >= b;
        case spv::OpIEqual:
            return a == b;
        case spv::OpINotEqual:
            return a != b;
        default:
            return std::nullopt;
    }
}

// The trips allowed by one exiting block's test, if it is an induction test.
std::optional<std::int64_t> tripsOfExit(const SpirvModule& module, const ControlFlowGraph& graph,
                                        const NaturalLoop& loop, int exiting) {
    const SpirvInstruction& branch = graph.block(exiting).terminator();
    const std::uint32_t trueTarget = branch.operands.at(1);
    const bool trueStays = loop.inBody[static_cast<std::size_t>(graph.indexOf(trueTarget))];
    const SpirvInstruction* condition = module.definition(branch.operands.at(0));
    if (condition == nullptr || condition->operands.size() != 2 ||
        !compare(condition->opcode, 0, 0)) {
        return std::nullopt;
    }
    const std::uint32_t left = condition->operands[0];
    const std::uint32_t right = condition->operands[1];
    const bool constantOnRight = module.integerConstant(right).has_value();
    const std::optional<std::int64_t> bound =
        module.integerConstant(constantOnRight ? right : left);
    if (!bound) {
        return std::nullopt;
    }
    const std::optional<Induction> induction =
        inductionOf(module, graph, loop, constantOnRight ? left : right);
    if (!induction) {
        return std::nullopt;
    }
    // Count the tests that keep the loop going.
    std::int64_t stays = 0;
    std::int64_t i = induction->start;
    for (;; ++stays, i += induction->step) {
        if (stays > kMaximumTrips) {
            return std::nullopt;
        }
        const std::int64_t tested = induction->comparesNextValue ? i + induction->step : i;
        const bool result = *compare(condition->opcode, constantOnRight ? tested : *bound,
                                     constantOnRight ? *bound : tested);
        if (result != trueStays) {
            break;
        }
    }
    // A test in the header runs before the body: the body runs once per passed test. A test
    // further down runs after (part of) the body: once more.
    return exiting == loop.header ? stays : stays + 1;
}

}  // namespace

std::optional<std::int64_t> constantTripCount(const SpirvModule& module,
                                              const ControlFlowGraph& graph, int loopIndex) {
    const NaturalLoop& loop = graph.loops().at(static_cast<std::size_t>(loopIndex));

    // A do-once loop (merge-return's wrapper in older optimizers): every back edge is a branch
    // on a constant that leaves.
    const bool onceOnly = std::all_of(loop.latches.begin(), loop.latches.end(), [&](int latch) {
        const SpirvInstruction& branch = graph.block(latch).terminator();
        if (branch.opcode != spv::OpBranchConditional) {
            return false;
        }
        const std::optional<bool> constant = module.booleanConstant(branch.operands.at(0));
        if (!constant) {
            return false;
        }
        const std::uint32_t taken = *constant ? branch.operands.at(1) : branch.operands.at(2);
        return graph.indexOf(taken) != loop.header;
    });
    if (onceOnly) {
        return 1;
    }

    std::optional<std::int64_t> trips;
    for (std::size_t b = 0; b < graph.blockCount(); ++b) {
        const int block = static_cast<int>(b);
        if (!loop.inBody[b] || graph.block(block).terminator().opcode != spv::OpBranchConditional) {
            continue;
        }
        const std::vector<int>& out = graph.successors(block);
        const bool exits = std::any_of(out.begin(), out.end(), [&](int target) {
            return !loop.inBody[static_cast<std::size_t>(target)];
        });
        if (!exits) {
            continue;
        }
        const std::optional<std::int64_t> bound = tripsOfExit(module, graph, loop, block);
        if (bound && (!trips || *bound < *trips)) {
            trips = bound;
        }
    }
    return trips;
}

}  // namespace vpe::shader_cost
