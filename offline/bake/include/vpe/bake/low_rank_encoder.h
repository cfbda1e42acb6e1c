// SPDX-License-Identifier: MIT
// Low-rank compression of a coefficient map for the device: the projector's board is
// memory-bandwidth bound, and the 66 coefficients of a texel (M = 10, RGB) are strongly
// correlated, so each texel is stored as R weights of a per-map principal basis:
//   coefficient(x) = μ + Σ_r w_r(x) · B_r
// with μ and B (R × C floats) in the bundle's metadata and w as half floats in ⌈R/4⌉ RGBA16F
// layers — 8·⌈R/4⌉ bytes per texel instead of 8·⌈C/4⌉ (136 at M = 10).
#pragma once

#include <cstddef>
#include <vector>

namespace vpe::bake {

struct LowRankCode {
    int channels = 0;            // C
    int rank = 0;                // R
    std::vector<float> mean;     // C
    std::vector<float> basis;    // R × C, orthonormal rows, by decreasing variance
    std::vector<float> weights;  // R per texel
    // Share of the coefficients' variance (over the texels used) each component explains.
    std::vector<double> explained;
};

struct LowRankOptions {
    int rank = 12;
    // Texels the basis is estimated from, evenly spread: the covariance of 66 channels is
    // settled long before a 2048² map's 4 M texels.
    std::size_t maxSamples = 200000;
    unsigned threads = 1;
};

// `coefficients` holds C values per texel; texels whose `valid` is 0 (if given) are left out
// of the basis and coded as μ. Throws InputError for a rank outside 1..C.
LowRankCode encodeLowRank(const std::vector<float>& coefficients, int channels,
                          const std::vector<unsigned char>& valid, const LowRankOptions& options);

// The coefficients the code stands for (C per texel), for measuring what compression costs.
std::vector<float> decodeLowRank(const LowRankCode& code);

}  // namespace vpe::bake
