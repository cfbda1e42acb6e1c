// SPDX-License-Identifier: MIT
// MaterialCoding: the material's codes and their GLSL (see the header).
#include "material_codes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vpe::renderer::gles {

namespace {

int nearest(float scaled, int low, int high) {
    const float code = std::floor(scaled + 0.5f);
    if (!(code >= static_cast<float>(low))) {  // NaN too
        return low;
    }
    return code > static_cast<float>(high) ? high : static_cast<int>(code);
}

}  // namespace

MaterialCoding::MaterialCoding(int basisSize) {
    if (basisSize < 1) {
        throw std::invalid_argument("a material coding needs at least one θs function");
    }
    largest_.assign(static_cast<std::size_t>(basisSize), 0.0f);
}

void MaterialCoding::cover(std::span<const float> map) {
    const std::size_t values = 3 * (1 + largest_.size());
    if (map.size() % values != 0) {
        throw std::invalid_argument("a θs material map's size is not a multiple of its " +
                                    std::to_string(values) + " values a texel");
    }
    for (std::size_t t = 0; t < map.size(); t += values) {
        for (std::size_t c = 0; c < 3; ++c) {
            low_ = std::min(low_, map[t + c]);
            high_ = std::max(high_, map[t + c]);
        }
        for (std::size_t i = 3; i < values; ++i) {
            float& largest = largest_[i / 3 - 1];
            largest = std::max(largest, std::fabs(map[t + i]));
        }
    }
}

float MaterialCoding::basisStep(int k) const {
    return largest_[static_cast<std::size_t>(k)] / static_cast<float>(kBasisCodeMax);
}

int MaterialCoding::diffuseCode(float kd) const {
    return nearest((kd - diffuseLow()) * (static_cast<float>(kDiffuseCodeMax) / diffuseSpan()), 0,
                   kDiffuseCodeMax);
}

int MaterialCoding::basisCode(int k, float u) const {
    const float step = basisStep(k);
    return step > 0.0f ? nearest(u * (1.0f / step), -kBasisCodeMax, kBasisCodeMax) : 0;
}

float MaterialCoding::diffuse(int code) const {
    return diffuseLow() +
           diffuseSpan() * (static_cast<float>(code) / static_cast<float>(kDiffuseCodeMax));
}

float MaterialCoding::basis(int k, int code) const {
    return basisStep(k) * static_cast<float>(code);
}

std::vector<float> scaledThetaTable(std::span<const float> table, const MaterialCoding& coding) {
    const auto k = static_cast<std::size_t>(coding.basisSize());
    if (k == 0 || table.size() % k != 0) {
        throw std::invalid_argument("a θs table of " + std::to_string(table.size()) +
                                    " values is not for " + std::to_string(k) + " functions");
    }
    std::vector<float> scaled(table.begin(), table.end());
    const float unit = coding.frameUnit();
    for (std::size_t i = 0; i < scaled.size(); ++i) {
        scaled[i] *= coding.basisStep(static_cast<int>(i % k)) / unit;
    }
    return scaled;
}

int basisWordsPerChannel(int basisSize) {
    return (basisSize + 3) / 4;
}

int materialCodeWords(int basisSize) {
    return 3 * basisWordsPerChannel(basisSize) + 1;
}

int materialCodeLayers(int basisSize) {
    return (materialCodeWords(basisSize) + 3) / 4;
}

std::uint32_t packSignedBytes(const std::array<int, 4>& codes) {
    std::uint32_t word = 0;
    for (std::size_t b = 0; b < 4; ++b) {
        word |= (static_cast<std::uint32_t>(codes[b]) & 0xffu) << (8 * b);
    }
    return word;
}

std::array<int, 4> unpackSignedBytes(std::uint32_t word) {
    std::array<int, 4> codes{};
    for (std::size_t b = 0; b < 4; ++b) {
        codes[b] = static_cast<std::int8_t>(static_cast<std::uint8_t>(word >> (8 * b)));
    }
    return codes;
}

std::string materialCodesGlsl() {
    return R"GLSL(
// packSignedBytes: code b in byte b, two's complement (codes integral in [−127, 127]).
int vpePackSignedBytes(vec4 codes) {
    ivec4 bytes = ivec4(codes) & 255;
    return bytes.x | (bytes.y << 8) | (bytes.z << 16) | (bytes.w << 24);
}

// unpackSignedBytes: each byte to the top, then back with its sign (three operations a byte:
// two shifts and a conversion; the top byte needs one shift).
vec4 vpeSignedBytes(int word) {
    return vec4(ivec4(word << 24, word << 16, word << 8, word) >> 24);
}
)GLSL";
}

}  // namespace vpe::renderer::gles
