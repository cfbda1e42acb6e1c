// SPDX-License-Identifier: MIT
// A viewing zone: the visitors' eyes a show's view-dependent light is drawn for when several
// stand around the object at once (docs/visitors.md). One frame serves them all, so each surface
// point is drawn for one eye: the mean direction towards the eyes that see its side, each
// weighted by how squarely it sees it (the cosine at the point's geometric normal), at their
// mean distance. The weights fade to 0 as an eye reaches the point's horizon, so the eye moves
// smoothly over the surface (no edge where a visitor drops out). The renderer's shaders compute
// the same (renderer/gles/shading_glsl.cpp, vpeZoneViewer), once per projector pixel at load.
#pragma once

#include <array>
#include <cmath>
#include <span>

#include "vpe/proto/vector_types.h"

namespace vpe::proto {

// The most eyes a bundle's zone holds (the shaders' uniform array).
inline constexpr int kMaxViewingZone = 16;

// The eye the point at `position` is drawn for; `fallback` (the bundle's viewer) when the zone
// is empty or no eye sees the point's side.
template <typename T>
Vec3<T> zoneEye(const Vec3<T>& position, const Vec3<T>& geometricNormal,
                std::span<const std::array<float, 3>> zone, const Vec3<T>& fallback) {
    Vec3<T> direction{0, 0, 0};
    T weightSum = 0, distanceSum = 0;
    for (const std::array<float, 3>& eye : zone) {
        const Vec3<T> to{T(eye[0]) - position.x, T(eye[1]) - position.y, T(eye[2]) - position.z};
        const T distance = std::sqrt(dot(to, to));
        if (!(distance > 0)) {
            continue;
        }
        const T weight = dot(geometricNormal, to) / distance;
        if (!(weight > 0)) {
            continue;
        }
        direction = {direction.x + weight * to.x / distance, direction.y + weight * to.y / distance,
                     direction.z + weight * to.z / distance};
        weightSum += weight;
        distanceSum += weight * distance;
    }
    if (!(weightSum > 0)) {
        return fallback;
    }
    const T scale = distanceSum / weightSum / std::sqrt(dot(direction, direction));
    return {position.x + scale * direction.x, position.y + scale * direction.y,
            position.z + scale * direction.z};
}

}  // namespace vpe::proto
