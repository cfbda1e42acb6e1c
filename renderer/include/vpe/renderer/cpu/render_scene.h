// SPDX-License-Identifier: MIT
// RenderScene: everything one frame depends on, as plain data (views and values), and the
// options of a render call.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "vpe/renderer/cpu/image_buffers.h"
#include "vpe/renderer/cpu/material_textures.h"
#include "vpe/renderer/cpu/measured_light.h"
#include "vpe/renderer/cpu/projector_model.h"
#include "vpe/renderer/cpu/render_mesh.h"
#include "vpe/renderer/cpu/screen_surface.h"
#include "vpe/renderer/cpu/virtual_light.h"

namespace vpe::renderer {

struct RenderScene {
    RenderMesh mesh;
    ProjectorModel projector;
    ScreenSurface surface;
    MaterialTextures material;
    VirtualLight light;
    Vec3d viewer{0, 0, 1};  // the eye the view-dependent terms are rendered for, metres
    // A viewing zone (several visitors at once; bundle 1.6), when not empty: each point is drawn
    // for proto::zoneEye, the mean direction to the eyes that see its side, and `viewer` where
    // none does (docs/visitors.md).
    std::vector<std::array<float, 3>> viewingZone;
    // The light measured on site (bundle 1.4): when set, the compensation inverts it instead of
    // `surface` and the projector's irradiance scale, and projector.response is the response
    // above black. Shared: the maps are the projector's size, the same for every frame.
    std::shared_ptr<const MeasuredLightMaps> measuredLight;
    // In a show of several projectors (bundle 1.5's blend): this projector's share of the light
    // per pixel (the projector's size), s ∈ [0, 1]; the compensation aims for s of the light
    // above the floor. None: all of it.
    std::shared_ptr<const FloatImage> lightShare;
};

struct RenderOptions {
    // Global exposure: the target radiance L is gain · E_light · f. > 0.
    double gain = 1.0;
    // Worker threads (the caller's thread is one of them); 0: std::thread's
    // hardware_concurrency. Results do not depend on it.
    int threads = 0;
};

// Why the scene cannot be rendered, as a phrase ("material: region 1 weights: 10 values,
// expected 12"); "" when it can.
std::string checkRenderScene(const RenderScene& scene);

}  // namespace vpe::renderer
