// SPDX-License-Identifier: MIT
// Interreflection: one bounce of light from the object onto itself, as radiosity between
// patches of its surface — what makes a concave neck or a flared lip glow where the projector
// lights the facing side, and what a structured-light decoder must not mistake for the pattern.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/surface_point.h"

#include "projector_light.h"

namespace vpe::renderer::procam {

class Interreflection {
public:
    using AlbedoAt = std::function<std::array<double, 3>(const SurfacePoint&)>;
    // Whether the projector lights a point with a normal, its P·cos θ/d² and projector pixel.
    using ProjectorReach = std::function<bool(const Vec3d&, const Vec3d&, double&, Vec2d&)>;

    // Patches: the object's surface sampled at the centres of a grid × grid lattice of its
    // texture space (one patch per cell centre a triangle covers, the first triangle winning
    // where uvs overlap); each patch's direct light is averaged over 3 × 3 points of its cell.
    // Form factors between every pair of patches that face each other and see each other
    // (the caster's shadow test), as for a disc of the patch's area:
    //   E_i = Σ_j L_j · cos θ_i cos θ_j · A_j / (r² + A_j/π).
    Interreflection(const RenderMesh& mesh, std::uint32_t objectTriangles, int grid,
                    const AlbedoAt& albedoAt, const ProjectorReach& reach, const RayCaster& caster,
                    int threads);

    std::size_t patchCount() const { return patches_.size(); }

    // The irradiance each patch receives from all others for this frame (patches × 3): their
    // radiance ρ/π·(projector + ambient) spread by the form factors.
    std::vector<float> bounce(const ProjectorLight& light,
                              const std::array<double, 3>& ambient) const;
    // Bilinear between the patches of the four cells around (u, v); 0 where none.
    std::array<float, 3> lookup(const std::vector<float>& bounce, float u, float v) const;

private:
    struct Patch {
        Vec3d position, normal;
        double area = 0;
        std::array<double, 3> albedoOverPi{};
    };
    struct SubSample {
        float px, py, scale;  // projector pixel, S / samples
    };
    static constexpr int kSubSamples = 9;

    int grid_ = 0;
    std::vector<int> cellPatch_;  // grid × grid, −1 where no patch
    std::vector<Patch> patches_;
    std::vector<SubSample> subSamples_;  // kSubSamples per patch; scale 0 where unlit
    std::vector<float> formFactors_;     // patches × patches, receiver-major
};

}  // namespace vpe::renderer::procam
