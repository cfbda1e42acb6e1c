// SPDX-License-Identifier: MIT
// targetRadiance: sample the regions, evaluate the Fourier BRDF, scale by the light.
#include "target_radiance.h"

#include <algorithm>

#include "vpe/proto/surface_horizon.h"

#include "vector_math.h"

namespace vpe::renderer {

std::array<double, 3> targetRadiance(const RenderScene& scene, const SurfacePoint& point,
                                     const Vec3d& viewer, double gain) {
    const Vec3d toLight = scene.light.position - point.position;
    const Vec3d toViewer = viewer - point.position;
    const double lightDistance = length(toLight), viewerDistance = length(toViewer);
    if (!(lightDistance > 0) || !(viewerDistance > 0)) {
        return {0, 0, 0};
    }
    const Vec3d l = (1.0 / lightDistance) * toLight, v = (1.0 / viewerDistance) * toViewer;
    const Vec3d normal = shadingNormal(scene.material, point);
    // Below the horizon of either normal, toward the light or the viewer: no light at all.
    const double horizon =
        proto::horizonFactor(proto::dot(normal, l), proto::dot(point.geometricNormal, l),
                             proto::dot(normal, v), proto::dot(point.geometricNormal, v));
    if (horizon == 0) {
        return {0, 0, 0};
    }
    double coefficients[kMaxCoefficientsPerTexel];
    sampleMaterial(scene.material, point.uv, coefficients);
    const std::array<double, 3> f =
        evaluateMaterial(coefficients, scene.material.harmonics, normal, l, v);
    const std::array<double, 3> irradiance = scene.light.irradianceAt(point.position);
    std::array<double, 3> radiance{};
    for (std::size_t c = 0; c < 3; ++c) {
        radiance[c] = std::max(gain * horizon * irradiance[c] * f[c], 0.0);
    }
    return radiance;
}

}  // namespace vpe::renderer
