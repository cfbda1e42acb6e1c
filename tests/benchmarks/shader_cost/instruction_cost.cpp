// SPDX-License-Identifier: MIT
// InstructionCostModel: the counting rules, one SPIR-V opcode (or GLSL.std.450 function) each.
//
// FLOPs as GPU peak figures count them: one per scalar operation and component; a multiply-add
// two (V3D has no fused one: its add and multiply ALUs issue in parallel). Integer, bit, boolean
// and conversion operations one each, kept apart as int ops (and included in FLOPs). SFU
// operations (reciprocal, rsqrt, sqrt, log2, exp2, sin) apart. Lowerings of the functions
// hardware lacks follow Mesa: V3D's nir_to_vir.c (sin, cos, sign) and NIR's builtin builder /
// vtn_glsl450.c (atan, atan2, asin, acos, smoothstep); docs/shader-cost.md has the table.
#include "instruction_cost.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <glslang/SPIRV/GLSL.std.450.h>

namespace vpe::shader_cost {

namespace {

ShaderCost floatOps(std::int64_t count, std::int64_t sfu = 0) {
    ShaderCost cost;
    cost.floatOps = count;
    cost.sfu = sfu;
    return cost;
}

ShaderCost intOps(std::int64_t count) {
    ShaderCost cost;
    cost.intOps = count;
    return cost;
}

ShaderCost mixedOps(std::int64_t floats, std::int64_t ints, std::int64_t sfu) {
    ShaderCost cost;
    cost.floatOps = floats;
    cost.intOps = ints;
    cost.sfu = sfu;
    return cost;
}

bool isTextureFetch(spv::Op opcode) {
    switch (opcode) {
        case spv::OpImageSampleImplicitLod:
        case spv::OpImageSampleExplicitLod:
        case spv::OpImageSampleDrefImplicitLod:
        case spv::OpImageSampleDrefExplicitLod:
        case spv::OpImageSampleProjImplicitLod:
        case spv::OpImageSampleProjExplicitLod:
        case spv::OpImageSampleProjDrefImplicitLod:
        case spv::OpImageSampleProjDrefExplicitLod:
        case spv::OpImageFetch:
        case spv::OpImageGather:
        case spv::OpImageDrefGather:
        case spv::OpImageRead:
        case spv::OpImageSparseSampleImplicitLod:
        case spv::OpImageSparseSampleExplicitLod:
        case spv::OpImageSparseSampleDrefImplicitLod:
        case spv::OpImageSparseSampleDrefExplicitLod:
        case spv::OpImageSparseSampleProjImplicitLod:
        case spv::OpImageSparseSampleProjExplicitLod:
        case spv::OpImageSparseSampleProjDrefImplicitLod:
        case spv::OpImageSparseSampleProjDrefExplicitLod:
        case spv::OpImageSparseFetch:
        case spv::OpImageSparseGather:
        case spv::OpImageSparseDrefGather:
        case spv::OpImageSparseRead:
            return true;
        default:
            return false;
    }
}

// Instructions that cost nothing: data movement the register allocator or the uniform stream
// absorbs, control flow (its cost is the choice of path), declarations.
bool isFree(spv::Op opcode) {
    if (isBlockTerminator(opcode)) {
        return true;
    }
    switch (opcode) {
        case spv::OpNop:
        case spv::OpUndef:
        case spv::OpLine:
        case spv::OpNoLine:
        case spv::OpVariable:
        case spv::OpLoad:
        case spv::OpStore:
        case spv::OpCopyMemory:
        case spv::OpAccessChain:
        case spv::OpInBoundsAccessChain:
        case spv::OpPtrAccessChain:
        case spv::OpCopyObject:
        case spv::OpCopyLogical:
        case spv::OpCompositeConstruct:
        case spv::OpCompositeExtract:
        case spv::OpCompositeInsert:
        case spv::OpVectorShuffle:
        case spv::OpVectorExtractDynamic:  // free here: a compiler with constant indices folds it
        case spv::OpVectorInsertDynamic:
        case spv::OpTranspose:
        case spv::OpPhi:
        case spv::OpSampledImage:
        case spv::OpImage:
        case spv::OpImageWrite:  // a store, not a fetch
        case spv::OpImageQueryFormat:
        case spv::OpImageQueryOrder:
        case spv::OpImageQuerySizeLod:
        case spv::OpImageQuerySize:
        case spv::OpImageQueryLod:
        case spv::OpImageQueryLevels:
        case spv::OpImageQuerySamples:
        case spv::OpFunctionParameter:
        case spv::OpFunctionCall:  // the callee's path is added by the path analysis
        case spv::OpSelectionMerge:
        case spv::OpLoopMerge:
        case spv::OpDemoteToHelperInvocation:
        case spv::OpControlBarrier:
        case spv::OpMemoryBarrier:
            return true;
        default:
            return false;
    }
}

}  // namespace

InstructionCostModel::InstructionCostModel(const SpirvModule& module,
                                           std::map<std::string, int> texelBytes,
                                           std::set<std::string> cached)
    : module_(module), texelBytes_(std::move(texelBytes)), cached_(std::move(cached)) {}

bool InstructionCostModel::knows(const SpirvInstruction& instruction) const {
    return rule(instruction).has_value();
}

ShaderCost InstructionCostModel::cost(const SpirvInstruction& instruction) const {
    return rule(instruction).value_or(ShaderCost{});
}

std::optional<ShaderCost> InstructionCostModel::rule(const SpirvInstruction& instruction) const {
    if (isFree(instruction.opcode)) {
        return ShaderCost{};
    }
    const std::int64_t n = module_.componentCount(instruction.resultType);
    const auto operandComponents = [&](std::size_t index) {
        return index < instruction.operands.size()
                   ? module_.valueComponents(instruction.operands[index])
                   : std::int64_t{0};
    };
    if (isTextureFetch(instruction.opcode)) {
        return textureCost(instruction);
    }
    switch (instruction.opcode) {
        // Float arithmetic, comparisons, selects: one per component.
        case spv::OpFNegate:
            return negationIsFolded(instruction) ? ShaderCost{} : floatOps(n);
        case spv::OpFAdd:
        case spv::OpFSub:
        case spv::OpFMul:
        case spv::OpVectorTimesScalar:
        case spv::OpMatrixTimesScalar:
        case spv::OpFOrdEqual:
        case spv::OpFUnordEqual:
        case spv::OpFOrdNotEqual:
        case spv::OpFUnordNotEqual:
        case spv::OpFOrdLessThan:
        case spv::OpFUnordLessThan:
        case spv::OpFOrdGreaterThan:
        case spv::OpFUnordGreaterThan:
        case spv::OpFOrdLessThanEqual:
        case spv::OpFUnordLessThanEqual:
        case spv::OpFOrdGreaterThanEqual:
        case spv::OpFUnordGreaterThanEqual:
        case spv::OpIsNan:
        case spv::OpIsInf:
        case spv::OpIsFinite:
        case spv::OpIsNormal:
        case spv::OpOrdered:
        case spv::OpUnordered:
        case spv::OpLessOrGreater:
        case spv::OpSelect:
        case spv::OpDPdx:
        case spv::OpDPdy:
        case spv::OpDPdxFine:
        case spv::OpDPdyFine:
        case spv::OpDPdxCoarse:
        case spv::OpDPdyCoarse:
            return floatOps(n);
        // fwidth = |dFdx| + |dFdy|.
        case spv::OpFwidth:
        case spv::OpFwidthFine:
        case spv::OpFwidthCoarse:
            return floatOps(5 * n);
        case spv::OpFDiv:
            return divisionCost(instruction);
        // mod(x, y) = x − y·floor(x·(1/y)): a reciprocal and four operations.
        case spv::OpFRem:
        case spv::OpFMod:
            return floatOps(4 * n, n);
        // Products: a dot product of k components is k multiplies and k − 1 adds.
        case spv::OpDot: {
            const std::int64_t k = operandComponents(0);
            return floatOps(2 * k - 1);
        }
        case spv::OpMatrixTimesVector:
            return floatOps(n * (2 * operandComponents(1) - 1));
        case spv::OpVectorTimesMatrix:
            return floatOps(n * (2 * operandComponents(0) - 1));
        case spv::OpMatrixTimesMatrix: {
            const std::int64_t inner =
                module_.matrixColumns(module_.typeOf(instruction.operands.at(0)));
            return floatOps(n * (2 * inner - 1));
        }
        case spv::OpOuterProduct:
            return floatOps(n);
        // Integer, bit, boolean and conversion operations: one per component.
        case spv::OpIAdd:
        case spv::OpISub:
        case spv::OpIMul:
        case spv::OpUDiv:
        case spv::OpSDiv:
        case spv::OpUMod:
        case spv::OpSRem:
        case spv::OpSMod:
        case spv::OpSNegate:
        case spv::OpShiftRightLogical:
        case spv::OpShiftRightArithmetic:
        case spv::OpShiftLeftLogical:
        case spv::OpBitwiseOr:
        case spv::OpBitwiseXor:
        case spv::OpBitwiseAnd:
        case spv::OpNot:
        case spv::OpBitFieldInsert:
        case spv::OpBitFieldSExtract:
        case spv::OpBitFieldUExtract:
        case spv::OpBitReverse:
        case spv::OpBitCount:
        case spv::OpIEqual:
        case spv::OpINotEqual:
        case spv::OpUGreaterThan:
        case spv::OpSGreaterThan:
        case spv::OpUGreaterThanEqual:
        case spv::OpSGreaterThanEqual:
        case spv::OpULessThan:
        case spv::OpSLessThan:
        case spv::OpULessThanEqual:
        case spv::OpSLessThanEqual:
        case spv::OpLogicalEqual:
        case spv::OpLogicalNotEqual:
        case spv::OpLogicalOr:
        case spv::OpLogicalAnd:
        case spv::OpLogicalNot:
        case spv::OpConvertFToU:
        case spv::OpConvertFToS:
        case spv::OpConvertSToF:
        case spv::OpConvertUToF:
        case spv::OpUConvert:
        case spv::OpSConvert:
        case spv::OpFConvert:
        case spv::OpQuantizeToF16:
        case spv::OpBitcast:
            return intOps(n);
        // Two results (sum and carry, low and high word).
        case spv::OpIAddCarry:
        case spv::OpISubBorrow:
        case spv::OpUMulExtended:
        case spv::OpSMulExtended:
            return intOps(2 * operandComponents(0));
        // any/all of k booleans: k − 1 ands or ors.
        case spv::OpAny:
        case spv::OpAll:
            return intOps(operandComponents(0) - 1);
        case spv::OpExtInst:
            return extendedCost(instruction);
        default:
            return std::nullopt;
    }
}

std::optional<ShaderCost> InstructionCostModel::extendedCost(
    const SpirvInstruction& instruction) const {
    if (instruction.operands.size() < 2 || instruction.operands[0] != module_.glslStd450()) {
        return ShaderCost{};  // another instruction set (debug information): no code
    }
    const std::int64_t n = module_.componentCount(instruction.resultType);
    // k: components of the first argument (length, dot-like functions reduce over them).
    const std::int64_t k =
        instruction.operands.size() > 2 ? module_.valueComponents(instruction.operands[2]) : n;
    switch (static_cast<GLSLstd450>(instruction.operands[1])) {
        case GLSLstd450Round:
        case GLSLstd450RoundEven:
        case GLSLstd450Trunc:
        case GLSLstd450FAbs:
        case GLSLstd450Floor:
        case GLSLstd450Ceil:
        case GLSLstd450Fract:
        case GLSLstd450Radians:
        case GLSLstd450Degrees:
        case GLSLstd450FMin:
        case GLSLstd450FMax:
        case GLSLstd450NMin:
        case GLSLstd450NMax:
            return floatOps(n);
        case GLSLstd450SAbs:
        case GLSLstd450UMin:
        case GLSLstd450SMin:
        case GLSLstd450UMax:
        case GLSLstd450SMax:
        case GLSLstd450FindILsb:
        case GLSLstd450FindSMsb:
        case GLSLstd450FindUMsb:
            return intOps(n);
        // sign: two compares and two conditional moves (V3D's ntq_fsign).
        case GLSLstd450FSign:
            return floatOps(4 * n);
        case GLSLstd450SSign:
            return intOps(4 * n);
        case GLSLstd450FClamp:
        case GLSLstd450NClamp:
            return floatOps(2 * n);
        case GLSLstd450UClamp:
        case GLSLstd450SClamp:
            return intOps(2 * n);
        case GLSLstd450FMix:
        case GLSLstd450IMix:
            return floatOps(3 * n);
        case GLSLstd450Step:  // compare + select
            return floatOps(2 * n);
        // t = clamp((x − e0) / (e1 − e0)), t·t·(3 − 2t): 2 subs, a division, a clamp, a
        // multiply-add and 2 multiplies.
        case GLSLstd450SmoothStep:
            return floatOps(9 * n, n);
        case GLSLstd450Fma:
            return floatOps(2 * n);
        // modf: trunc and a subtraction.
        case GLSLstd450Modf:
        case GLSLstd450ModfStruct:
            return floatOps(2 * k);
        // frexp: exponent field extracted, biased and masked; ldexp: shifted in and added.
        case GLSLstd450Frexp:
        case GLSLstd450FrexpStruct:
            return intOps(3 * k);
        case GLSLstd450Ldexp:
            return intOps(2 * n);
        // V3D's ntq_fsincos: x·(1/π) [+ 0.5 for cos], round, subtract, SIN, then the sign from
        // the period: float→int, shift, xor.
        case GLSLstd450Sin:
            return mixedOps(3 * n, 3 * n, n);
        case GLSLstd450Cos:
            return mixedOps(4 * n, 3 * n, n);
        // tan = sin / cos.
        case GLSLstd450Tan:
            return mixedOps(8 * n, 6 * n, 3 * n);
        // vtn_glsl450.c build_asin: |x|, three multiply-adds, 1 − |x|, sqrt, a multiply, a
        // subtraction, sign(x) and its multiply; acos adds π/2 − asin.
        case GLSLstd450Asin:
            return floatOps(15 * n, n);
        case GLSLstd450Acos:
            return floatOps(16 * n, n);
        // nir_atan: |x|, min, max, a division, x², five odd powers, six scaled terms summed,
        // the range fix-up (compare, select, two multiply-adds), the sign and its multiply.
        case GLSLstd450Atan:
            return floatOps(32 * n, n);
        // nir_atan2: the half-plane flip and scaling (10 operations and a reciprocal), the
        // |s/t| selection, nir_atan, the flip's multiply-add and the sign selection.
        case GLSLstd450Atan2:
            return floatOps(53 * n, 2 * n);
        // Hyperbolic functions by their exponential and logarithmic definitions (each exp or
        // log a multiply and an SFU operation).
        case GLSLstd450Sinh:
        case GLSLstd450Cosh:
            return floatOps(4 * n, 2 * n);
        case GLSLstd450Tanh:
            return floatOps(5 * n, 3 * n);
        case GLSLstd450Asinh:
        case GLSLstd450Acosh:
            return floatOps(4 * n, 2 * n);
        case GLSLstd450Atanh:
            return floatOps(5 * n, 2 * n);
        // pow(x, y) = exp2(y·log2 x).
        case GLSLstd450Pow:
            return floatOps(n, 2 * n);
        case GLSLstd450Exp:
        case GLSLstd450Log:
            return floatOps(n, n);
        case GLSLstd450Exp2:
        case GLSLstd450Log2:
        case GLSLstd450Sqrt:
        case GLSLstd450InverseSqrt:
            return floatOps(0, n);
        // Cofactor expansion.
        case GLSLstd450Determinant: {
            const std::int64_t size =
                module_.matrixColumns(module_.typeOf(instruction.operands[2]));
            return floatOps(size == 2 ? 3 : size == 3 ? 14 : 63);
        }
        // Adjugate (cofactors), determinant from them, one reciprocal, the scaling.
        case GLSLstd450MatrixInverse: {
            const std::int64_t size = module_.matrixColumns(instruction.resultType);
            return floatOps(size == 2 ? 9 : size == 3 ? 41 : 247, 1);
        }
        // Packing: one operation per unpacked component.
        case GLSLstd450PackSnorm4x8:
        case GLSLstd450PackUnorm4x8:
        case GLSLstd450PackSnorm2x16:
        case GLSLstd450PackUnorm2x16:
        case GLSLstd450PackHalf2x16:
        case GLSLstd450PackDouble2x32:
            return intOps(k);
        // Unpacking as V3D's NIR options lower it (lower_unpack_*): a half is one move with
        // the ALU's 16-bit input unpack; a unorm is extract, convert, scale (3 per component),
        // a snorm one more (the clamp at −1).
        case GLSLstd450UnpackHalf2x16:
        case GLSLstd450UnpackDouble2x32:
            return intOps(n);
        case GLSLstd450UnpackUnorm2x16:
        case GLSLstd450UnpackUnorm4x8:
            return intOps(3 * n);
        case GLSLstd450UnpackSnorm2x16:
        case GLSLstd450UnpackSnorm4x8:
            return intOps(4 * n);
        // length = sqrt(dot(v, v)); of a scalar, |x|.
        case GLSLstd450Length:
            return k == 1 ? floatOps(1) : floatOps(2 * k - 1, 1);
        case GLSLstd450Distance:
            return k == 1 ? floatOps(2) : floatOps(k + 2 * k - 1, 1);
        // 6 multiplies, 3 subtractions.
        case GLSLstd450Cross:
            return floatOps(9);
        // normalize = v · inversesqrt(dot(v, v)); of a scalar, sign(x).
        case GLSLstd450Normalize:
            return k == 1 ? floatOps(4) : floatOps(2 * k - 1 + k, 1);
        // dot, compare, negate, select.
        case GLSLstd450FaceForward:
            return floatOps(2 * k - 1 + 1 + 2 * k);
        // I − 2·dot(N, I)·N: dot, doubling, a multiply-add per component.
        case GLSLstd450Reflect:
            return floatOps(2 * k - 1 + 1 + 2 * k);
        // k' = 1 − η²(1 − d²) (5), k' < 0, sqrt, η·d + sqrt (2), η·I − t·N (3 per component),
        // select.
        case GLSLstd450Refract:
            return floatOps(6 * k + 7, 1);
        // Interpolation at another position: the plane equation, a multiply-add per component.
        case GLSLstd450InterpolateAtCentroid:
        case GLSLstd450InterpolateAtSample:
        case GLSLstd450InterpolateAtOffset:
            return floatOps(2 * n);
        default:
            return std::nullopt;
    }
}

// A division is a reciprocal (SFU) and a multiply, per component, but as a driver compiles it
// (fdiv → fmul(a, frcp(b)), common subexpressions merged, constants folded): one reciprocal
// per distinct non-constant divisor value (a vector divided by a scalar splat takes one), none
// for a constant divisor, and no multiply when the dividend is 1.0.
ShaderCost InstructionCostModel::divisionCost(const SpirvInstruction& instruction) const {
    const std::int64_t n = module_.componentCount(instruction.resultType);
    const std::uint32_t dividend = instruction.operands.at(0);
    const std::uint32_t divisor = instruction.operands.at(1);
    std::int64_t reciprocals = n;
    if (module_.isFloatConstant(divisor)) {
        reciprocals = 0;
    } else if (const SpirvInstruction* definition = module_.definition(divisor);
               definition != nullptr && definition->opcode == spv::OpCompositeConstruct &&
               static_cast<std::int64_t>(definition->operands.size()) == n) {
        std::vector<std::uint32_t> distinct;
        for (const std::uint32_t constituent : definition->operands) {
            if (!module_.isFloatConstant(constituent) &&
                std::find(distinct.begin(), distinct.end(), constituent) == distinct.end()) {
                distinct.push_back(constituent);
            }
        }
        reciprocals = static_cast<std::int64_t>(distinct.size());
    }
    const std::int64_t multiplies = module_.isFloatConstant(dividend, 1.0f) ? 0 : n;
    return floatOps(multiplies, reciprocals);
}

// The optimizer's multiply-add fusion writes a·b − c as fma(a, b, −c); a negation that only
// feeds additions, subtractions and multiply-adds is a subtraction on any GPU, not an operation.
bool InstructionCostModel::negationIsFolded(const SpirvInstruction& instruction) const {
    const std::vector<const SpirvInstruction*>& users = module_.users(instruction.result);
    return !users.empty() &&
           std::all_of(users.begin(), users.end(), [&](const SpirvInstruction* user) {
               if (user->opcode == spv::OpFAdd || user->opcode == spv::OpFSub) {
                   return true;
               }
               return user->opcode == spv::OpExtInst && user->operands.size() == 5 &&
                      user->operands[0] == module_.glslStd450() &&
                      user->operands[1] == GLSLstd450Fma;
           });
}

ShaderCost InstructionCostModel::textureCost(const SpirvInstruction& instruction) const {
    ShaderCost cost;
    cost.textureFetches = 1;
    switch (instruction.opcode) {
        case spv::OpImageSampleProjImplicitLod:
        case spv::OpImageSampleProjExplicitLod:
        case spv::OpImageSampleProjDrefImplicitLod:
        case spv::OpImageSampleProjDrefExplicitLod:
        case spv::OpImageSparseSampleProjImplicitLod:
        case spv::OpImageSparseSampleProjExplicitLod:
        case spv::OpImageSparseSampleProjDrefImplicitLod:
        case spv::OpImageSparseSampleProjDrefExplicitLod:
            // The projective divide: a reciprocal of q and a multiply per other coordinate.
            cost.sfu = 1;
            cost.floatOps = module_.valueComponents(instruction.operands.at(1)) - 1;
            break;
        default:
            break;
    }
    // Texels a fetch reads: texelFetch / imageLoad one; filtered samples and gathers a 2 × 2
    // footprint (bilinear, no mipmaps assumed).
    const bool singleTexel = instruction.opcode == spv::OpImageFetch ||
                             instruction.opcode == spv::OpImageRead ||
                             instruction.opcode == spv::OpImageSparseFetch ||
                             instruction.opcode == spv::OpImageSparseRead;
    const std::string sampler = samplerName(instruction.operands.at(0));
    const auto bytes = texelBytes_.find(sampler);
    if (bytes == texelBytes_.end()) {
        cost.fetchesWithoutFormat = 1;
    } else {
        cost.textureBytes = (singleTexel ? 1 : 4) * bytes->second;
        // From memory: one texel a pixel (neighbours share a footprint), none from a cached table.
        cost.memoryReadBytes = cached_.count(sampler) > 0 ? 0 : bytes->second;
    }
    return cost;
}

std::string InstructionCostModel::samplerName(std::uint32_t id) const {
    // Back through OpSampledImage / OpImage / copies and loads to the uniform variable.
    for (int depth = 0; depth < 64; ++depth) {
        const SpirvInstruction* definition = module_.definition(id);
        if (definition == nullptr) {
            return "";
        }
        switch (definition->opcode) {
            case spv::OpVariable:
                return module_.name(id);
            case spv::OpLoad:
            case spv::OpSampledImage:
            case spv::OpImage:
            case spv::OpCopyObject:
            case spv::OpAccessChain:
            case spv::OpInBoundsAccessChain:
                id = definition->operands.at(0);
                break;
            default:
                return "";
        }
    }
    return "";
}

}  // namespace vpe::shader_cost
