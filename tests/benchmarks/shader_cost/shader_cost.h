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
    // Bytes the fetches bring from memory (DRAM) per pixel: one texel a fetch of a texture that
    // streams through the cache (a filtered fetch's 2 × 2 footprint is shared with the pixel's
    // neighbours, each texel read once), none from a table declared cached (small enough to
    // stay in the TMU's cache for the whole frame).
    std::int64_t memoryReadBytes = 0;
    std::int64_t memoryWriteBytes = 0;  // the colour outputs' texels, per shaded pixel

    std::int64_t memoryBytes() const { return memoryReadBytes + memoryWriteBytes; }

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
        memoryReadBytes += other.memoryReadBytes;
        memoryWriteBytes += other.memoryWriteBytes;
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
        scaled.memoryReadBytes = memoryReadBytes * count;
        scaled.memoryWriteBytes = memoryWriteBytes * count;
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
