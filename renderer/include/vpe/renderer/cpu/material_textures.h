// SPDX-License-Identifier: MIT
// MaterialTextures: the virtual material on the screen object's UV atlas — per region a
// Fourier BRDF coefficient map and a weight map (the paper's eq. 20) — and its sampling.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "vpe/proto/fourier_brdf.h"
#include "vpe/renderer/cpu/surface_point.h"
#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer {

// Views of caller-owned float arrays, width × height texels each, row 0 the TOP row of the
// image. Texel (x, y) of a coefficient map holds C = 3·(2M + 2) values at
// [(y·width + x)·C, +C): value 3·k + c is coefficient k (fourier_brdf.h order kd, a0, a1, b1,
// …, aM, bM) of colour channel c (R, G, B) — proto::bundleCoefficientIndex(k, c), the
// bundle's "fourier_brdf:k_major_rgb". A weight map holds one float per texel; the weights
// of all regions add up to 1 at every texel (not checked). Empty weights mean 1 everywhere
// (a single region, or a composed map). A relief map holds the detail normal's x and y per texel
// (proto/detail_normal.h: tangent space, x along +u, y along +v; z = √(1 − x² − y²)) at
// [(y·width + x)·2, +2); empty: no relief, (0, 0, 1).
struct MaterialRegion {
    std::span<const float> coefficients;
    std::span<const float> weights;
    std::span<const float> detailNormals;
};

struct MaterialTextures {
    int harmonics = 0;  // M, 0 … proto::kMaxHarmonics
    int width = 0, height = 0;
    // The maps tile in u (the bundle's wrap_u): sampling wraps around in u, so that texel 0
    // and texel width − 1 are neighbours; otherwise (and always in v) it clamps to the edge.
    bool wrapU = false;
    std::vector<MaterialRegion> regions;

    int coefficientsPerChannel() const { return proto::coefficientCount(harmonics); }
    int coefficientsPerTexel() const { return 3 * coefficientsPerChannel(); }
};

// The largest coefficientsPerTexel(): the size of sampleMaterial's output buffer.
inline constexpr int kMaxCoefficientsPerTexel = 3 * proto::coefficientCount(proto::kMaxHarmonics);

// Why the textures cannot be rendered, as a phrase; "" when they can.
std::string checkMaterialTextures(const MaterialTextures& material);

// The four texels around texture coordinate uv and their bilinear weights: continuous texel
// coordinates x = u·width − 0.5, y = (1 − v)·height − 0.5 (row 0 the top), clamped to the
// outermost texel centres (clamp to edge) or, for u when it wraps, taken modulo the width (GL's
// REPEAT: left of texel 0's centre the taps are texels width − 1 and 0). Texel index
// y·width + x. The GLES renderer's weight pass mirrors it (vpeBilinearWeight).
struct BilinearFootprint {
    std::size_t texel[4];
    double weight[4];
};
BilinearFootprint bilinearFootprint(int width, int height, const Vec2d& uv, bool wrapU);

// The blended coefficients at texture coordinate uv, in the texel layout above (3·k + c):
//   Σ_regions bilinear(weights)(uv) · bilinear(coefficients)(uv)
// — each map sampled on its own, as a GPU samples two textures. Bilinear with texel centres
// at ((x + 0.5)/width, 1 − (y + 0.5)/height) in uv, i.e. continuous texel coordinates
// (u·width − 0.5, (1 − v)·height − 0.5); clamp to edge, or in u wrapping around (GL's REPEAT)
// when material.wrapU. Writes coefficientsPerTexel() values.
void sampleMaterial(const MaterialTextures& material, const Vec2d& uv, double* coefficients);

// Whether any region carries a relief map.
bool hasRelief(const MaterialTextures& material);

// The blended detail normal at uv, not normalized (proto::applyDetailNormal normalizes):
//   Σ_regions bilinear(weights)(uv) · detailNormalFromXy(bilinear(x, y)(uv))
// — each region's x and y sampled bilinearly, as a GPU samples an RG texture, then z restored;
// a region without a relief map contributes (0, 0, 1). Same footprint as sampleMaterial.
Vec3d sampleDetailNormal(const MaterialTextures& material, const Vec2d& uv);

// The normal a surface point is shaded with: the mesh's shading normal, or with a relief, that
// normal tilted by the blended detail normal through the point's tangent frame
// (proto::tangentFrame of the normal and the triangle's ∂X/∂u, ∂X/∂v; proto::applyDetailNormal).
// The projector's irradiance on the plaster keeps the mesh's normal: the screen is smooth.
Vec3d shadingNormal(const MaterialTextures& material, const SurfacePoint& point);

// Radiance per unit irradiance f(θd, θs) of each channel for blended coefficients (as
// sampleMaterial writes them), with proto's evaluator and reflection geometry: n, toLight and
// toViewer are unit vectors pointing away from the surface point. Not clamped.
std::array<double, 3> evaluateMaterial(const double* coefficients, int harmonics,
                                       const Vec3d& normal, const Vec3d& toLight,
                                       const Vec3d& toViewer);

}  // namespace vpe::renderer
