// SPDX-License-Identifier: MIT
// The white screen seen by the viewer: the radiance a projector level gives (forward model)
// and the projector level that gives a wanted radiance (compensation).
#pragma once

#include <array>

#include "vpe/renderer/cpu/projector_model.h"
#include "vpe/renderer/cpu/screen_surface.h"
#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer {

// S = P · max(cos θp, 0) / d²: the irradiance at X per unit relative output r(level), with
// n the unit normal at X (projector_model.h).
double projectorIrradianceScale(const ProjectorModel& projector, const Vec3d& point,
                                const Vec3d& normal);

// Forward: the radiance of the plaster lit with relative outputs r (per channel) through the
// scale S: ρ/π · (S·r + E_ambient).
std::array<double, 3> screenRadiance(const ScreenSurface& surface, double irradianceScale,
                                     const std::array<double, 3>& relativeOutput);

struct CompensatedPixel {
    std::array<double, 3> level{};  // drive levels in [0, 1]
    bool clippedHigh = false;       // some channel needs more than full output
    bool clippedLow = false;        // some channel needs less than the black level
    // The largest global gain at which no channel would need more than full output (+∞ when
    // no channel wants light), in absolute terms: the target was rendered at `gain`.
    double gainLimit = 0;
};

// Inverse: per channel, the wanted relative output
//   r = (π·L/ρ − E_ambient) / S
// (L the target radiance at `gain`), then level = response⁻¹(r). r > 1 clips to level 1
// (clippedHigh), r below the black level r(0) clips to level 0 (clippedLow). With S = 0 (the
// projector grazes or sees the back), r is +∞ when π·L/ρ > E_ambient, −∞ when below, and
// 0 when equal. gainLimit = gain · min_c ρ_c·(S + E_ambient,c) / (π·L_c) over channels with
// L_c > 0.
CompensatedPixel compensatePixel(const ScreenSurface& surface,
                                 const proto::ResponseFunction& response, double irradianceScale,
                                 const std::array<double, 3>& target, double gain);

}  // namespace vpe::renderer
