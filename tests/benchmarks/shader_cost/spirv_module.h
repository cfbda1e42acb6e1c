// SPDX-License-Identifier: MIT
// SpirvModule: a SPIR-V binary read into instructions, types, names and functions of blocks.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

// spv::HasResultAndType, the table of which opcodes have a result type and id.
#ifndef SPV_ENABLE_UTILITY_CODE
#define SPV_ENABLE_UTILITY_CODE
#endif
#include <glslang/SPIRV/spirv.hpp>

namespace vpe::shader_cost {

struct SpirvInstruction {
    spv::Op opcode = spv::OpNop;
    std::uint32_t resultType = 0;         // 0 when the instruction has none
    std::uint32_t result = 0;             // 0 when the instruction has none
    std::vector<std::uint32_t> operands;  // the words after the result type and id
};

// A basic block: its instructions end with the merge instruction (if any) and the terminator.
struct SpirvBlock {
    std::uint32_t label = 0;
    std::span<const SpirvInstruction> instructions;
    std::vector<std::uint32_t> successors;  // labels, in the terminator's order
    const SpirvInstruction& terminator() const { return instructions.back(); }
    // The OpLoopMerge of a loop header, or nullptr.
    const SpirvInstruction* loopMerge() const;
};

struct SpirvFunction {
    std::uint32_t id = 0;
    std::vector<SpirvBlock> blocks;  // the entry block first
};

enum class ScalarKind { Float, Integer, Boolean, Other };

class SpirvModule {
public:
    // Throws std::runtime_error when the words are not a SPIR-V module this reader understands.
    explicit SpirvModule(std::span<const std::uint32_t> words);
    SpirvModule(const SpirvModule&) = delete;
    SpirvModule& operator=(const SpirvModule&) = delete;

    // The instruction that defines an id (types, constants, variables, results), or nullptr.
    const SpirvInstruction* definition(std::uint32_t id) const;
    const SpirvFunction* function(std::uint32_t id) const;
    // The function of the fragment entry point (the first one if several; throws if none).
    std::uint32_t fragmentEntryPoint() const;
    // The OpName of an id, or "".
    std::string name(std::uint32_t id) const;
    // The id of the imported GLSL.std.450 instruction set, or 0.
    std::uint32_t glslStd450() const { return glslStd450_; }

    // Components in a value of the type: 1 for scalars, n for vectors, columns × rows for
    // matrices, the sum of the members for structs, length × element for arrays.
    std::int64_t componentCount(std::uint32_t type) const;
    // Components in the value an id holds (its result type's).
    std::int64_t valueComponents(std::uint32_t id) const;
    // The columns of a matrix type (0 for other types).
    std::int64_t matrixColumns(std::uint32_t type) const;
    ScalarKind scalarKind(std::uint32_t type) const;
    std::uint32_t typeOf(std::uint32_t id) const;
    std::optional<std::int64_t> integerConstant(std::uint32_t id) const;
    std::optional<bool> booleanConstant(std::uint32_t id) const;
    // The value of a 32-bit float OpConstant, or nullopt.
    std::optional<float> floatConstant(std::uint32_t id) const;
    // Whether the id is a float constant (scalar or composite) whose components are all
    // `value`; with no value, whether it is a float constant at all.
    bool isFloatConstant(std::uint32_t id, std::optional<float> value = std::nullopt) const;
    // The instructions inside functions that name the id among their operands. Literal operands
    // are not told apart from ids, so this may list an instruction too many, never one too few.
    const std::vector<const SpirvInstruction*>& users(std::uint32_t id) const;

private:
    void readInstructions(std::span<const std::uint32_t> words);
    void buildFunctions();
    std::vector<std::uint32_t> successorsOf(const SpirvInstruction& terminator) const;

    std::vector<SpirvInstruction> instructions_;
    std::unordered_map<std::uint32_t, std::size_t> definitions_;  // id → instruction index
    std::unordered_map<std::uint32_t, std::string> names_;
    std::unordered_map<std::uint32_t, std::vector<const SpirvInstruction*>> users_;
    std::unordered_map<std::uint32_t, SpirvFunction> functions_;
    std::vector<std::uint32_t> fragmentEntryPoints_;
    std::uint32_t glslStd450_ = 0;
};

// An instruction that ends a block: a branch, a switch, a return, a kill or unreachable.
bool isBlockTerminator(spv::Op opcode);

// The string literal starting at operands[first] (nul-terminated, four bytes a word).
std::string literalString(const std::vector<std::uint32_t>& operands, std::size_t first);

}  // namespace vpe::shader_cost
