// SPDX-License-Identifier: MIT
// VirtualLight::irradianceAt.
#include "vpe/renderer/cpu/virtual_light.h"

#include "vector_math.h"

namespace vpe::renderer {

std::array<double, 3> VirtualLight::irradianceAt(const Vec3d& point) const {
    if (!inverseSquare) {
        return intensity;
    }
    const Vec3d toLight = position - point;
    const double falloff = referenceDistance * referenceDistance / proto::dot(toLight, toLight);
    return {intensity[0] * falloff, intensity[1] * falloff, intensity[2] * falloff};
}

}  // namespace vpe::renderer
