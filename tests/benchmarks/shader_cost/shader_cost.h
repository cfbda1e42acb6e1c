// SPDX-License-Identifier: MIT
// ShaderCost: what one shaded pixel costs along one path of a shader (ALU, SFU, texture).
#pragma once

#include <cstdint>

namespace vpe::shader_cost {

// An SFU operation (reciprocal, rsqrt, log2, exp2, sin) costs as much issue time as this many
// FLOPs (docs/pi-headroom.md: VideoCore IV's SFU takes 4 cycles; V3D is assumed alike).
inline constexpr std::int64_t kSfuFlopEquivalent = 4;

struct ShaderCost {
    std::int64_t floatOps = 0;  // float ALU operations, per component
    std::int64_t intOps = 0;    // integer, bit, boolean and conversion operations, per component
    std::int64_t sfu = 0;       // special-function operations, per component
    std::int64_t textureFetches = 0;  // texture instructions, per call
    std::int64_t textureBytes = 0;    // bytes those fetches request, where the format is known
    std::int64_t fetchesWithoutFormat = 0;  // fetches whose sampler has no declared format

    // FLOPs as peak figures count them: integer operations occupy the same ALU slots.
    std::int64_t flops() const { return floatOps + intOps; }
    std::int64_t flopEquivalent() const { return flops() + kSfuFlopEquivalent * sfu; }

    ShaderCost& operator+=(const ShaderCost& other) {
        floatOps += other.floatOps;
        intOps += other.intOps;
        sfu += other.sfu;
        textureFetches += other.textureFetches;
        textureBytes += other.textureBytes;
        fetchesWithoutFormat += other.fetchesWithoutFormat;
        return *this;
    }
    ShaderCost times(std::int64_t count) const {
        ShaderCost scaled;
        scaled.floatOps = floatOps * count;
        scaled.intOps = intOps * count;
        scaled.sfu = sfu * count;
        scaled.textureFetches = textureFetches * count;
        scaled.textureBytes = textureBytes * count;
        scaled.fetchesWithoutFormat = fetchesWithoutFormat * count;
        return scaled;
    }
};

inline ShaderCost operator+(ShaderCost a, const ShaderCost& b) {
    return a += b;
}

// The order in which paths are compared: ALU issue time first, texture fetches on a tie.
inline bool costsMore(const ShaderCost& a, const ShaderCost& b) {
    if (a.flopEquivalent() != b.flopEquivalent()) {
        return a.flopEquivalent() > b.flopEquivalent();
    }
    return a.textureFetches > b.textureFetches;
}

}  // namespace vpe::shader_cost
