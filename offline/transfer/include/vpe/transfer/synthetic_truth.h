// SPDX-License-Identifier: MIT
// SyntheticTruth: the true material of a `vpe synth` capture laid on another object through the
// same texture layout as its fitted model — texel (x, y) is capture pixel (x, y) — so that the
// truth and the pipeline's rendering of the fitted model correspond pixel for pixel. The GGX +
// Lambert parameters (truth/parameters.exr) and the relief as a detail normal map: the true
// normals (truth/normals.exr) relative to the true macro shape (truth/macro-normals.exr), in
// the frame the fit measures its own relief in (normals/detail_normals.h).
#pragma once

#include <array>
#include <filesystem>
#include <vector>

#include "vpe/renderer/cpu/material_textures.h"
#include "vpe/renderer/cpu/surface_point.h"
#include "vpe/renderer/cpu/virtual_light.h"

namespace vpe::transfer {

class SyntheticTruth {
public:
    // `capture` is the folder `vpe synth --out` wrote (train/, truth/). Throws InputError naming
    // the file at fault.
    explicit SyntheticTruth(const std::filesystem::path& capture);
    SyntheticTruth(const SyntheticTruth&) = delete;  // the textures view its own arrays
    SyntheticTruth& operator=(const SyntheticTruth&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }
    // The true relief as the pipeline stores one (x and y per texel, proto/detail_normal.h).
    const std::vector<float>& detailNormals() const { return detail_; }

    // The radiance the true material sends toward `viewer` from a surface point under `light`:
    // E · H · (ρ + π f_spec)·max(n·l, 0) (synth/microfacet_brdf.h), n the point's normal tilted
    // by the true relief (renderer::shadingNormal, as the pipeline applies its own), H the
    // horizon factor of that normal and the geometric one (proto/surface_horizon.h). No cast
    // shadows: the virtual light casts none.
    std::array<double, 3> radiance(const renderer::SurfacePoint& point,
                                   const renderer::VirtualLight& light,
                                   const renderer::Vec3d& viewer) const;
    // Of that radiance, the part that depends on where the viewer stands: E · H · π f_spec ·
    // max(n·l, 0), the highlights (the rest, E · H · ρ · max(n·l, 0), is the same from anywhere
    // the horizon allows).
    std::array<double, 3> viewDependentRadiance(const renderer::SurfacePoint& point,
                                                const renderer::VirtualLight& light,
                                                const renderer::Vec3d& viewer) const;

private:
    std::array<double, 3> radianceParts(const renderer::SurfacePoint& point,
                                        const renderer::VirtualLight& light,
                                        const renderer::Vec3d& viewer,
                                        bool viewDependentOnly) const;

    int width_ = 0, height_ = 0;
    // Albedo RGB, then roughness, F0 and 0 per texel, read through the renderer's own sampler
    // (a "material" of M = 0: 6 values a texel) so that truth and pipeline sample a texel alike.
    std::vector<float> parameters_;
    std::vector<float> detail_;
    renderer::MaterialTextures parameterTextures_;
    renderer::MaterialTextures reliefTextures_;
};

}  // namespace vpe::transfer
