// SPDX-License-Identifier: MIT
// checkRenderScene: the checks every render call makes before touching a pixel.
#include "vpe/renderer/cpu/render_scene.h"

#include <cmath>

#include "vector_math.h"

namespace vpe::renderer {

std::string checkRenderScene(const RenderScene& scene) {
    if (auto problem = checkRenderMesh(scene.mesh); !problem.empty()) {
        return "mesh: " + problem;
    }
    if (auto problem = checkCamera(scene.projector.camera); !problem.empty()) {
        return "projector: " + problem;
    }
    if (!(scene.projector.peakIrradiance > 0) || !std::isfinite(scene.projector.peakIrradiance)) {
        return "projector: peak irradiance must be positive";
    }
    for (std::size_t c = 0; c < 3; ++c) {
        if (!(scene.surface.albedo[c] > 0 && scene.surface.albedo[c] <= 1)) {
            return "surface: albedo must be in (0, 1]";
        }
        if (!(scene.surface.ambientIrradiance[c] >= 0) ||
            !std::isfinite(scene.surface.ambientIrradiance[c])) {
            return "surface: ambient irradiance must be finite and ≥ 0";
        }
        if (!std::isfinite(scene.light.intensity[c])) {
            return "light: intensity must be finite";
        }
    }
    if (auto problem = checkMaterialTextures(scene.material); !problem.empty()) {
        return "material: " + problem;
    }
    if (const FloatImage* share = scene.lightShare.get(); share != nullptr) {
        if (share->width != scene.projector.camera.width ||
            share->height != scene.projector.camera.height) {
            return "light share: not the projector's size";
        }
        for (const float s : share->values) {
            if (!(s >= 0 && s <= 1)) {
                return "light share: a value outside [0, 1]";
            }
        }
    }
    if (!isFinite(scene.light.position) || !isFinite(scene.viewer)) {
        return "light and viewer positions must be finite";
    }
    if (scene.light.inverseSquare && !(scene.light.referenceDistance > 0)) {
        return "light: reference distance must be positive";
    }
    return "";
}

}  // namespace vpe::renderer
