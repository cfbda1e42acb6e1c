// SPDX-License-Identifier: MIT
// MeasuredLight: the compensation from what vpe radiometry measured on site instead of assumed
// albedo, gamma and ambient (offline/radiometry/: C = D + F · X · g). Per projector pixel the
// irradiance factor F and the floor D; for the projector the crosstalk X and, in the scene's
// ResponseFunction, the response above black g.
#pragma once

#include <array>
#include <vector>

#include "vpe/proto/response_function.h"
#include "vpe/renderer/cpu/lambertian_screen.h"

namespace vpe::renderer {

struct MeasuredLightMaps {
    int width = 0, height = 0;      // the projector's
    std::vector<float> irradiance;  // F: width·height·3, radiance per unit of a primary's output
    std::vector<float> floor;       // D: width·height·3, radiance at level 0
    std::array<double, 9> mixingInverse{1, 0, 0, 0, 1, 0, 0, 0, 1};  // X⁻¹, row-major
    // g⁻¹ as the device looks it up (the scene's response above black, tabulated).
    proto::InverseResponseTable inverseResponse{proto::ResponseFunction{}, 2};
};

// The share of a primary's full output up to which a pixel is compensated exactly; above it the
// wanted outputs roll off smoothly to full output (below).
inline constexpr double kHighlightKnee = 0.9;

// The largest irradiance factor a share divides F into (a half float's largest finite value:
// the device stores it so): outputs that small are black.
inline constexpr float kLargestSharedIrradiance = 65504.0f;

// F / s, the irradiance factor that makes the compensation aim for the share s of the light
// above the floor (bundle 1.5's blend), at most kLargestSharedIrradiance; s = 0 asks nothing.
inline float sharedIrradiance(float irradiance, float share) {
    return share > 0 && irradiance < share * kLargestSharedIrradiance ? irradiance / share
                                                                      : kLargestSharedIrradiance;
}

// The inverse of a row-major 3 × 3; std::invalid_argument when it is singular.
std::array<double, 9> inverse3x3(const std::array<double, 9>& m);

// Where a highlight needs more than the projector has: the outputs w (per primary, above black)
// scaled together — the hue kept — so that their largest, t, follows
//   t' = κ + (1 − κ) · tanh((t − κ) / (1 − κ))  for t > κ (κ = kHighlightKnee),
// continuous with its slope at κ and never reaching 1: no plateau, no band at the edge of
// the clipped region. Returns whether it rolled off.
bool rollOffHighlight(std::array<double, 3>& outputs);

// The inverse of the measured model at one projector pixel: the mixed output per camera channel
//   y = (L − D) / F,
// the primaries' outputs above black w = X⁻¹ · y, the highlight rolled off (clippedHigh: t > κ),
// negative outputs raised to 0 (clippedLow: the floor is brighter than the target), then
// level = g⁻¹(w) through the table the device uses. F ≤ 0 in some channel (no projector light
// measured there): each primary at level 1 where its channel's target is above the floor
// (clippedHigh), else 0. gainLimit: the largest gain at which t ≤ κ (+∞ when no primary grows with
// the gain).
CompensatedPixel compensateMeasuredPixel(const float* irradiance, const float* floor,
                                         const std::array<double, 9>& mixingInverse,
                                         const proto::InverseResponseTable& inverseResponse,
                                         const std::array<double, 3>& target, double gain);

}  // namespace vpe::renderer
