// SPDX-License-Identifier: MIT
// The two angles of the model, θd and θs, from normal, light and view directions.
#pragma once

#include <cmath>

#include "vpe/proto/vector_types.h"

namespace vpe::proto {

template <typename T>
struct ReflectionAngles {
    // cos θd = n·l, not clamped: the basis clamps the Lambert term, and a negative value tells
    // the caller the light is below the surface's horizon.
    T cosThetaD;
    // cos θs = r·v with r = 2(n·l)n − l the mirror direction of the light, clamped to [-1, 1].
    T cosThetaS;
};

// All three vectors are unit length and point away from the surface point: the normal, the
// direction towards the light and the direction towards the viewer.
template <typename T>
inline ReflectionAngles<T> reflectionAngles(const Vec3<T>& normal, const Vec3<T>& toLight,
                                            const Vec3<T>& toViewer) {
    using std::fmax;
    using std::fmin;
    const T nl = dot(normal, toLight);
    // r·v = 2(n·l)(n·v) − l·v: the mirror vector is never formed.
    const T rv = T(2) * nl * dot(normal, toViewer) - dot(toLight, toViewer);
    return {nl, fmin(fmax(rv, T(-1)), T(1))};
}

}  // namespace vpe::proto
