// SPDX-License-Identifier: MIT
// The projector-space material as a frame fetches it, in 20 bytes a pixel where half floats took
// 32: on a Pi 4 at 1080p memory binds before the ALU does (docs/pi-headroom.md).
//   - kd, the Lambert weight per channel: 10-bit unorm codes over [low, low + span] in an
//     RGB10_A2 texel, which the texture unit decodes at no ALU cost. kd carries most of a pixel's
//     light, and 8 bits cost the demo bundle 1 dB where 10 cost 0.1.
//   - u_kc, the weight of θs function k in channel c: signed bytes, one step per function shared
//     by the three channels, so that the step folds into the θs table (the frame multiplies a
//     code by h_k·step_k and nothing else). Four functions of one channel share a word: the frame
//     takes one dot product of a word's four codes with one row of the table.
// Bytes, not half floats, for the u: the frame's fetches are fixed at eight a pixel by the
// texture unit's rate (geometry, material, table, three response lookups), so the material must
// come in one 16-byte texel; sixteen halves would take two. Unpacking a byte costs three
// operations (shift, arithmetic shift, convert), paid for by the ALU headroom the frame won by
// moving work to load time.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace vpe::renderer::gles {

inline constexpr int kDiffuseCodeMax = 1023;  // 10-bit unorm
inline constexpr int kBasisCodeMax = 127;     // signed bytes, symmetric about 0

class MaterialCoding {
public:
    // A coding for K θs functions that covers nothing yet (every value 0).
    explicit MaterialCoding(int basisSize);
    // Widened to cover every value of `map` (renderer::thetaMaterialMap's layout: per texel kd
    // RGB, then u_j RGB for j = 0 … K − 1). A projector pixel's material is a convex blend of
    // texels (bilinear, the preset's weights, which sum to 1) times the viewer's horizon (≤ 1),
    // so a coding that covers every region's map covers it: no code clips. kd's range includes
    // 0, so that a dark pixel decodes exactly.
    void cover(std::span<const float> map);

    int basisSize() const { return static_cast<int>(largest_.size()); }
    // kd = diffuseLow() + diffuseSpan() · code / kDiffuseCodeMax.
    float diffuseLow() const { return low_; }
    float diffuseSpan() const { return high_ > low_ ? high_ - low_ : 1.0f; }
    // u_kc = basisStep(k) · code.
    float basisStep(int k) const;
    // The nearest code (floor(x + ½), as the material pass's GLSL), clamped to the range.
    int diffuseCode(float kd) const;
    int basisCode(int k, float u) const;
    float diffuse(int code) const;
    float basis(int k, int code) const;
    // The frame's unit, kd's span: f is evaluated in multiples of it, so that the sampler's
    // decoded kd codes (code/1023) multiply cos θd as they come and the table holds
    // h_k · step_k / unit. The radiance scale takes the unit back, once a frame.
    float frameUnit() const { return diffuseSpan(); }

private:
    float low_ = 0.0f, high_ = 0.0f;
    std::vector<float> largest_;  // the largest |u_kc| per k
};

// The θs table as the frame reads it: `table` (proto::ThetaTable's values, sample-major, K a
// sample) with function k scaled by step_k / frameUnit().
std::vector<float> scaledThetaTable(std::span<const float> table, const MaterialCoding& coding);

// The codes' words per pixel: per channel c, ⌈K/4⌉ words in which byte k % 4 (from the least
// significant) of word c·⌈K/4⌉ + k/4 is u_kc (two's complement); then one word of two half floats
// packed as GLSL's packHalf2x16: 1/S (low) and the geometric normal's z (high), the shading
// geometry's values that have no room in its own texel. In RGBA32I layers of four words.
int basisWordsPerChannel(int basisSize);
int materialCodeWords(int basisSize);
int materialCodeLayers(int basisSize);
std::uint32_t packSignedBytes(const std::array<int, 4>& codes);
std::array<int, 4> unpackSignedBytes(std::uint32_t word);

// GLSL defining the two sides of the byte codes:
//   int vpePackSignedBytes(vec4 codes)   — packSignedBytes (codes integral in [−127, 127])
//   vec4 vpeSignedBytes(int word)        — unpackSignedBytes, as floats
std::string materialCodesGlsl();

}  // namespace vpe::renderer::gles
