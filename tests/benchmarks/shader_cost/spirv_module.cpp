// SPDX-License-Identifier: MIT
// SpirvModule: reads the words of a SPIR-V binary (the layout of the SPIR-V specification, 2.3).
#include "spirv_module.h"

#include <bit>
#include <stdexcept>

namespace vpe::shader_cost {

namespace {

constexpr std::uint32_t kMagicNumber = 0x07230203;
constexpr std::size_t kHeaderWords = 5;

}  // namespace

std::string literalString(const std::vector<std::uint32_t>& operands, std::size_t first) {
    std::string text;
    for (std::size_t i = first; i < operands.size(); ++i) {
        for (int byte = 0; byte < 4; ++byte) {
            const char c = static_cast<char>((operands[i] >> (8 * byte)) & 0xffu);
            if (c == '\0') {
                return text;
            }
            text.push_back(c);
        }
    }
    return text;
}

const SpirvInstruction* SpirvBlock::loopMerge() const {
    if (instructions.size() >= 2 &&
        instructions[instructions.size() - 2].opcode == spv::OpLoopMerge) {
        return &instructions[instructions.size() - 2];
    }
    return nullptr;
}

SpirvModule::SpirvModule(std::span<const std::uint32_t> words) {
    if (words.size() < kHeaderWords || words[0] != kMagicNumber) {
        throw std::runtime_error("not a SPIR-V module (bad magic number)");
    }
    readInstructions(words.subspan(kHeaderWords));
    buildFunctions();
}

void SpirvModule::readInstructions(std::span<const std::uint32_t> words) {
    std::size_t at = 0;
    while (at < words.size()) {
        const std::uint32_t wordCount = words[at] >> 16;
        if (wordCount == 0 || at + wordCount > words.size()) {
            throw std::runtime_error("truncated SPIR-V instruction at word " +
                                     std::to_string(at + kHeaderWords));
        }
        SpirvInstruction instruction;
        instruction.opcode = static_cast<spv::Op>(words[at] & 0xffffu);
        bool hasResult = false;
        bool hasResultType = false;
        spv::HasResultAndType(instruction.opcode, &hasResult, &hasResultType);
        std::size_t operand = at + 1;
        if (hasResultType && operand < at + wordCount) {
            instruction.resultType = words[operand++];
        }
        if (hasResult && operand < at + wordCount) {
            instruction.result = words[operand++];
        }
        instruction.operands.assign(words.begin() + static_cast<std::ptrdiff_t>(operand),
                                    words.begin() + static_cast<std::ptrdiff_t>(at + wordCount));
        if (instruction.result != 0) {
            definitions_[instruction.result] = instructions_.size();
        }
        switch (instruction.opcode) {
            case spv::OpName:
                if (!instruction.operands.empty()) {
                    names_[instruction.operands[0]] = literalString(instruction.operands, 1);
                }
                break;
            case spv::OpEntryPoint:
                if (instruction.operands.size() >= 2 &&
                    instruction.operands[0] == spv::ExecutionModelFragment) {
                    fragmentEntryPoints_.push_back(instruction.operands[1]);
                }
                break;
            case spv::OpExtInstImport:
                if (literalString(instruction.operands, 0) == "GLSL.std.450") {
                    glslStd450_ = instruction.result;
                }
                break;
            default:
                break;
        }
        instructions_.push_back(std::move(instruction));
        at += wordCount;
    }
}

void SpirvModule::buildFunctions() {
    // Blocks refer to instructions_ by span: it does not change any more.
    SpirvFunction* current = nullptr;
    std::size_t blockStart = 0;
    std::uint32_t blockLabel = 0;
    for (std::size_t i = 0; i < instructions_.size(); ++i) {
        const SpirvInstruction& instruction = instructions_[i];
        if (current != nullptr) {
            for (const std::uint32_t operand : instruction.operands) {
                std::vector<const SpirvInstruction*>& users = users_[operand];
                if (users.empty() || users.back() != &instruction) {
                    users.push_back(&instruction);
                }
            }
        }
        switch (instruction.opcode) {
            case spv::OpFunction:
                current = &functions_[instruction.result];
                current->id = instruction.result;
                blockLabel = 0;
                break;
            case spv::OpFunctionEnd:
                current = nullptr;
                break;
            case spv::OpLabel:
                blockLabel = instruction.result;
                blockStart = i + 1;
                break;
            default:
                if (!isBlockTerminator(instruction.opcode)) {
                    break;
                }
                if (current == nullptr || blockLabel == 0) {
                    throw std::runtime_error("SPIR-V block terminator outside a block");
                }
                {
                    SpirvBlock block;
                    block.label = blockLabel;
                    block.instructions = std::span<const SpirvInstruction>(instructions_)
                                             .subspan(blockStart, i + 1 - blockStart);
                    block.successors = successorsOf(instruction);
                    current->blocks.push_back(std::move(block));
                }
                blockLabel = 0;
                break;
        }
    }
}

bool isBlockTerminator(spv::Op opcode) {
    switch (opcode) {
        case spv::OpBranch:
        case spv::OpBranchConditional:
        case spv::OpSwitch:
        case spv::OpReturn:
        case spv::OpReturnValue:
        case spv::OpKill:
        case spv::OpTerminateInvocation:
        case spv::OpUnreachable:
            return true;
        default:
            return false;
    }
}

std::vector<std::uint32_t> SpirvModule::successorsOf(const SpirvInstruction& terminator) const {
    const std::vector<std::uint32_t>& operands = terminator.operands;
    switch (terminator.opcode) {
        case spv::OpBranch:
            return {operands.at(0)};
        case spv::OpBranchConditional:
            return {operands.at(1), operands.at(2)};
        case spv::OpSwitch: {
            // Selector, default, then (literal, label) pairs; a 64-bit selector's literals take
            // two words.
            const std::uint32_t selectorType = typeOf(operands.at(0));
            const SpirvInstruction* type = definition(selectorType);
            const std::size_t literalWords =
                type != nullptr && type->opcode == spv::OpTypeInt && type->operands.at(0) == 64 ? 2
                                                                                                : 1;
            std::vector<std::uint32_t> targets{operands.at(1)};
            for (std::size_t i = 2 + literalWords; i < operands.size(); i += literalWords + 1) {
                targets.push_back(operands[i]);
            }
            return targets;
        }
        default:
            return {};
    }
}

const SpirvInstruction* SpirvModule::definition(std::uint32_t id) const {
    const auto found = definitions_.find(id);
    return found == definitions_.end() ? nullptr : &instructions_[found->second];
}

const SpirvFunction* SpirvModule::function(std::uint32_t id) const {
    const auto found = functions_.find(id);
    return found == functions_.end() ? nullptr : &found->second;
}

std::uint32_t SpirvModule::fragmentEntryPoint() const {
    if (fragmentEntryPoints_.empty()) {
        throw std::runtime_error("the SPIR-V module has no fragment entry point");
    }
    return fragmentEntryPoints_.front();
}

std::string SpirvModule::name(std::uint32_t id) const {
    const auto found = names_.find(id);
    return found == names_.end() ? std::string() : found->second;
}

std::uint32_t SpirvModule::typeOf(std::uint32_t id) const {
    const SpirvInstruction* instruction = definition(id);
    return instruction == nullptr ? 0 : instruction->resultType;
}

std::int64_t SpirvModule::componentCount(std::uint32_t type) const {
    const SpirvInstruction* instruction = definition(type);
    if (instruction == nullptr) {
        return 0;
    }
    switch (instruction->opcode) {
        case spv::OpTypeBool:
        case spv::OpTypeInt:
        case spv::OpTypeFloat:
            return 1;
        case spv::OpTypeVector:
            return instruction->operands.at(1);
        case spv::OpTypeMatrix:
            return instruction->operands.at(1) * componentCount(instruction->operands.at(0));
        case spv::OpTypeArray:
            return integerConstant(instruction->operands.at(1)).value_or(1) *
                   componentCount(instruction->operands.at(0));
        case spv::OpTypeStruct: {
            std::int64_t sum = 0;
            for (const std::uint32_t member : instruction->operands) {
                sum += componentCount(member);
            }
            return sum;
        }
        default:
            return 0;
    }
}

std::int64_t SpirvModule::valueComponents(std::uint32_t id) const {
    return componentCount(typeOf(id));
}

std::int64_t SpirvModule::matrixColumns(std::uint32_t type) const {
    const SpirvInstruction* instruction = definition(type);
    return instruction != nullptr && instruction->opcode == spv::OpTypeMatrix
               ? instruction->operands.at(1)
               : 0;
}

ScalarKind SpirvModule::scalarKind(std::uint32_t type) const {
    const SpirvInstruction* instruction = definition(type);
    if (instruction == nullptr) {
        return ScalarKind::Other;
    }
    switch (instruction->opcode) {
        case spv::OpTypeFloat:
            return ScalarKind::Float;
        case spv::OpTypeInt:
            return ScalarKind::Integer;
        case spv::OpTypeBool:
            return ScalarKind::Boolean;
        case spv::OpTypeVector:
        case spv::OpTypeMatrix:
        case spv::OpTypeArray:
            return scalarKind(instruction->operands.at(0));
        default:
            return ScalarKind::Other;
    }
}

std::optional<std::int64_t> SpirvModule::integerConstant(std::uint32_t id) const {
    const SpirvInstruction* instruction = definition(id);
    if (instruction == nullptr || instruction->opcode != spv::OpConstant ||
        instruction->operands.empty()) {
        return std::nullopt;
    }
    const SpirvInstruction* type = definition(instruction->resultType);
    if (type == nullptr || type->opcode != spv::OpTypeInt) {
        return std::nullopt;
    }
    const std::uint32_t width = type->operands.at(0);
    const bool isSigned = type->operands.at(1) != 0;
    if (width <= 32) {
        const std::uint32_t bits = instruction->operands[0];
        return isSigned ? static_cast<std::int64_t>(static_cast<std::int32_t>(bits))
                        : static_cast<std::int64_t>(bits);
    }
    if (instruction->operands.size() < 2) {
        return std::nullopt;
    }
    const std::uint64_t bits =
        instruction->operands[0] | (static_cast<std::uint64_t>(instruction->operands[1]) << 32);
    return static_cast<std::int64_t>(bits);
}

std::optional<float> SpirvModule::floatConstant(std::uint32_t id) const {
    const SpirvInstruction* instruction = definition(id);
    if (instruction == nullptr || instruction->opcode != spv::OpConstant ||
        instruction->operands.size() != 1) {
        return std::nullopt;
    }
    const SpirvInstruction* type = definition(instruction->resultType);
    if (type == nullptr || type->opcode != spv::OpTypeFloat || type->operands.at(0) != 32) {
        return std::nullopt;
    }
    return std::bit_cast<float>(instruction->operands[0]);
}

bool SpirvModule::isFloatConstant(std::uint32_t id, std::optional<float> value) const {
    const SpirvInstruction* instruction = definition(id);
    if (instruction == nullptr) {
        return false;
    }
    if (instruction->opcode == spv::OpConstantComposite) {
        for (const std::uint32_t constituent : instruction->operands) {
            if (!isFloatConstant(constituent, value)) {
                return false;
            }
        }
        return !instruction->operands.empty();
    }
    if (instruction->opcode == spv::OpConstantNull) {
        return scalarKind(instruction->resultType) == ScalarKind::Float &&
               (!value || *value == 0.0f);
    }
    const std::optional<float> constant = floatConstant(id);
    return constant && (!value || *constant == *value);
}

const std::vector<const SpirvInstruction*>& SpirvModule::users(std::uint32_t id) const {
    static const std::vector<const SpirvInstruction*> kNone;
    const auto found = users_.find(id);
    return found == users_.end() ? kNone : found->second;
}

std::optional<bool> SpirvModule::booleanConstant(std::uint32_t id) const {
    const SpirvInstruction* instruction = definition(id);
    if (instruction == nullptr) {
        return std::nullopt;
    }
    if (instruction->opcode == spv::OpConstantTrue) {
        return true;
    }
    if (instruction->opcode == spv::OpConstantFalse) {
        return false;
    }
    return std::nullopt;
}

}  // namespace vpe::shader_cost
