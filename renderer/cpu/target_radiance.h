// SPDX-License-Identifier: MIT
// The material's radiance toward a viewer at a surface point: what the projector frame aims
// for and what the direct view shows. Private to the CPU renderer.
#pragma once

#include <array>

#include "vpe/renderer/cpu/render_scene.h"
#include "vpe/renderer/cpu/surface_point.h"

namespace vpe::renderer {

// L = gain · H · E_light(X) · f(θd, θs), each channel clamped to ≥ 0, with H the horizon
// factor of proto/surface_horizon.h (0 when the light or the viewer is below the horizon of
// the shading or the geometric normal, or sits on X).
std::array<double, 3> targetRadiance(const RenderScene& scene, const SurfacePoint& point,
                                     const Vec3d& viewer, double gain);

}  // namespace vpe::renderer
