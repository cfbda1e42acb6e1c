// SPDX-License-Identifier: MIT
// IEEE binary16 ↔ float: reading a bundle's half-float payloads on the CPU (the GPU samples
// them directly), and writing half floats the way GL rounds them (round to nearest even).
#pragma once

#include <bit>
#include <cstdint>

namespace vpe::proto {

inline float halfToFloat(std::uint16_t half) {
    const std::uint32_t sign = static_cast<std::uint32_t>(half & 0x8000u) << 16;
    const std::uint32_t exponent = (half >> 10) & 0x1fu;
    std::uint32_t mantissa = half & 0x3ffu;
    if (exponent == 0x1f) {  // infinity or NaN
        return std::bit_cast<float>(sign | 0x7f800000u | (mantissa << 13));
    }
    if (exponent != 0) {  // normal: rebias 15 → 127
        return std::bit_cast<float>(sign | ((exponent + 112u) << 23) | (mantissa << 13));
    }
    if (mantissa == 0) {
        return std::bit_cast<float>(sign);
    }
    // Subnormal half: value = mantissa · 2^-24, a normal float.
    int shift = 0;
    while ((mantissa & 0x400u) == 0) {
        mantissa <<= 1;
        ++shift;
    }
    mantissa &= 0x3ffu;
    return std::bit_cast<float>(sign | (static_cast<std::uint32_t>(113 - shift) << 23) |
                                (mantissa << 13));
}

// float → binary16, rounded to nearest, ties to even (as GL's float-to-half conversion):
// overflow gives ±infinity, small values become subnormal halves or ±0, NaN stays a NaN.
inline std::uint16_t floatToHalf(float value) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    const auto sign = static_cast<std::uint16_t>((bits >> 16) & 0x8000u);
    const std::uint32_t exponent = (bits >> 23) & 0xffu;
    const std::uint32_t mantissa = bits & 0x7fffffu;
    if (exponent == 0xff) {  // infinity or NaN (a quiet NaN keeps a mantissa bit)
        return static_cast<std::uint16_t>(sign | 0x7c00u | (mantissa != 0 ? 0x200u : 0u));
    }
    const int halfExponent = static_cast<int>(exponent) - 127 + 15;
    if (halfExponent >= 0x1f) {
        return static_cast<std::uint16_t>(sign | 0x7c00u);
    }
    // The 24-bit significand (implicit 1 unless the float is subnormal), shifted so that its
    // top bit lands on the half's implicit bit (normal) or below it (subnormal half).
    const std::uint32_t significand = exponent != 0 ? (mantissa | 0x800000u) : mantissa;
    const int shift = halfExponent > 0 ? 13 : 14 - halfExponent;
    if (shift > 24) {
        return sign;  // below half the smallest subnormal: ±0
    }
    std::uint32_t rounded = significand >> shift;
    const std::uint32_t remainder = significand & ((1u << shift) - 1u);
    const std::uint32_t halfway = 1u << (shift - 1);
    if (remainder > halfway || (remainder == halfway && (rounded & 1u) != 0)) {
        ++rounded;  // may carry into the exponent: still the right encoding
    }
    // Normal: `rounded` holds the implicit bit (0x400); a carry to 0x800 steps the exponent
    // (to infinity from the largest binade). Subnormal: a carry to 0x400 is the smallest normal.
    const std::uint32_t magnitude =
        halfExponent > 0 ? (static_cast<std::uint32_t>(halfExponent - 1) << 10) + rounded : rounded;
    return static_cast<std::uint16_t>(sign | magnitude);
}

}  // namespace vpe::proto
