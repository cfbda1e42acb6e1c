// SPDX-License-Identifier: MIT
// The bundle's θs basis (proto/MODEL.md, "Rendering in a θs basis"): the K functions of θs that
// keep the most of the textures' θs parts, by a principal component analysis in the ∫₀^π
// metric. The device renders every texel's θs part projected onto them
// (proto/theta_basis.h); it has no linear algebra library, so the bake chooses them.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace vpe::bake {

// S = Σ g gᵀ over the θs parts g of the texels added (2M + 1 values per colour channel, in
// theta_basis.h's function order: model coefficients 1 … 2M + 1), each channel of each texel
// one sample. Uncentered: the device projects g itself, not g minus a mean.
class ThetaMoment {
public:
    explicit ThetaMoment(int harmonics);

    // Adds every texel of a coefficient map (3·(2M + 2) values per texel, the bundle's order
    // 3·k + c); texels whose `valid` is 0 (when given, one per texel) are left out.
    void add(std::span<const float> coefficients, std::span<const unsigned char> valid = {});

    int harmonics() const { return harmonics_; }
    std::size_t samples() const { return samples_; }
    // S, (2M + 1) × (2M + 1), symmetric, row-major.
    const std::vector<double>& moment() const { return moment_; }

private:
    int harmonics_;
    std::size_t samples_ = 0;
    std::vector<double> moment_;
};

struct ThetaBasisFit {
    std::vector<float> functions;  // K × (2M + 1), as proto::BundleModel::thetaBasis
    // Σ ∫₀^π (g projected)² / Σ ∫₀^π g² over the samples: the share of the θs parts' second
    // moment the K functions keep (1 when every g is 0).
    double energyKept = 1;
};

// How many of the 2M + 1 θs functions are numerically independent over [0, π]: the Gram
// matrix's eigenvalues above 1e-10 of the largest (M = 10: 18 of 21). Sums of sines match sums
// of cosines on a half period to 1e-13, so no basis orthonormal in float has more functions.
int independentThetaFunctions(int harmonics);

// With G = V Λ Vᵀ (proto::thetaGram, eigenvalues below 1e-10 of the largest dropped) and
// G^½ = V Λ^½ Vᵀ: the eigenvectors e_j of G^½ S G^½ with the K largest eigenvalues, as
// functions h_j = G^-½ e_j, which are orthonormal under G. Each function's largest-magnitude
// coefficient is positive, so the basis does not flip between bakes. Throws InputError when K
// is outside 1 … independentThetaFunctions(M), or when the functions, rounded to floats, fail
// proto::checkThetaBasis (possible only for K near that limit: see the .cpp).
ThetaBasisFit fitThetaBasis(const ThetaMoment& moment, int size);

}  // namespace vpe::bake
