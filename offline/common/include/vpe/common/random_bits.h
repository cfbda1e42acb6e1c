// SPDX-License-Identifier: MIT
// Counter-based random numbers: value(i) depends only on a seed and i (splitmix64's
// finalizer), so seeded results do not depend on evaluation order or the thread count. Used by
// the synthetic captures, the quilter's tie-breaking, the stroke patterns and the quilt metrics.
#pragma once

#include <cstdint>

namespace vpe::common {

// splitmix64's finalizer of value + the golden-ratio increment: a bijective 64-bit hash.
constexpr std::uint64_t mixBits(std::uint64_t value) {
    value += 0x9e3779b97f4a7c15ull;
    value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ull;
    value = (value ^ (value >> 27)) * 0x94d049bb133111ebull;
    return value ^ (value >> 31);
}

// The top 53 bits as a double in [0, 1).
constexpr double uniformFromBits(std::uint64_t bits) {
    return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

}  // namespace vpe::common
