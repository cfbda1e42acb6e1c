// SPDX-License-Identifier: MIT
// The horizon of a surface point (proto/MODEL.md, "The horizon"): no light reaches it from a
// light below its horizon, and none leaves it toward a viewer below its horizon. One smooth
// factor, shared by the CPU reference and (mirrored) the GLSL, that multiplies the radiance.
#pragma once

#include <algorithm>

namespace vpe::proto {

// The factor ramps from 0 at cos = 0 to 1 at cos = kHorizonWidth (≈ 2.9° above the horizon),
// smoothly (C¹), so that the terminator is a soft edge a few projector pixels wide instead of
// a one-pixel step that aliases as the light moves. Below the horizon it is exactly 0.
inline constexpr double kHorizonWidth = 0.05;

// smoothstep(0, kHorizonWidth, cosine).
template <typename T>
inline T horizonFactor(T cosine) {
    const T t = std::clamp(cosine * T(1.0 / kHorizonWidth), T(0), T(1));
    return t * t * (T(3) - T(2) * t);
}

// Both the shading normal and the geometric normal must see the light and the viewer: a
// shading normal (interpolated, or a relief's) can lean over the geometric horizon, and
// testing it alone would let light leak onto the dark side. Each side ramps on the lower of
// its two cosines: one ramp where two cost a frame twice the arithmetic, the same factor
// wherever either cosine is past the ramp, and 0 below either horizon as before.
template <typename T>
inline T horizonFactor(T shadingToLight, T geometricToLight, T shadingToViewer,
                       T geometricToViewer) {
    return horizonFactor(std::min(shadingToLight, geometricToLight)) *
           horizonFactor(std::min(shadingToViewer, geometricToViewer));
}

}  // namespace vpe::proto
