// SPDX-License-Identifier: MIT
// The relief (proto/MODEL.md, "The relief"): a detail normal per texel in tangent space — its
// tilt relative to the macro shape along the texture's u and v directions — and how a renderer
// applies it through the surface's tangent frame. One definition for the fit (which measures
// it on the capture), the CPU reference and, mirrored, the GLSL.
#pragma once

#include <algorithm>
#include <cmath>

#include "vpe/proto/vector_types.h"

namespace vpe::proto {

// An orthonormal frame at a surface point: t along the texture's +u direction, b along its +v
// direction (v up, OBJ / GL: toward the texture's top row), n the macro (shading) normal.
template <typename T>
struct TangentFrame {
    Vec3<T> t, b, n;
};

// The frame of a shading normal n and the surface's texture directions tangentU = ∂X/∂u and
// tangentV = ∂X/∂v (any lengths): t is tangentU made orthogonal to n (Gram–Schmidt), b = n × t,
// turned to agree with tangentV — so a mirrored texture mapping mirrors the relief with the
// material. When tangentU has no part orthogonal to n (a degenerate mapping), t comes from
// tangentV instead; when neither has, from any direction orthogonal to n.
template <typename T>
TangentFrame<T> tangentFrame(const Vec3<T>& n, const Vec3<T>& tangentU, const Vec3<T>& tangentV) {
    using std::sqrt;
    const auto along = [&n](const Vec3<T>& v) {
        const T d = dot(v, n);
        return Vec3<T>{v.x - d * n.x, v.y - d * n.y, v.z - d * n.z};
    };
    // Relative to the vectors' own lengths: a mapping's scale (metres per texture) is arbitrary.
    const auto usable = [](const Vec3<T>& projected, const Vec3<T>& original) {
        return dot(projected, projected) > T(1e-12) * dot(original, original) &&
               dot(projected, projected) > T(0);
    };
    TangentFrame<T> frame;
    frame.n = n;
    const Vec3<T> u = along(tangentU), v = along(tangentV);
    if (usable(u, tangentU)) {
        frame.t = normalized(u);
        frame.b = cross(n, frame.t);
        if (dot(frame.b, tangentV) < T(0)) {
            frame.b = Vec3<T>{-frame.b.x, -frame.b.y, -frame.b.z};
        }
    } else if (usable(v, tangentV)) {
        frame.b = normalized(v);
        frame.t = cross(frame.b, n);
    } else {
        const Vec3<T> axis = std::fabs(n.x) < T(0.9) ? Vec3<T>{1, 0, 0} : Vec3<T>{0, 1, 0};
        frame.t = normalized(along(axis));
        frame.b = cross(n, frame.t);
    }
    return frame;
}

// The shading normal with the relief: normalize(d.x·t + d.y·b + d.z·n) for a detail normal d
// (unit, d.z > 0: (0, 0, 1) is no relief).
template <typename T>
Vec3<T> applyDetailNormal(const TangentFrame<T>& frame, const Vec3<T>& detail) {
    return normalized(Vec3<T>{detail.x * frame.t.x + detail.y * frame.b.x + detail.z * frame.n.x,
                              detail.x * frame.t.y + detail.y * frame.b.y + detail.z * frame.n.y,
                              detail.x * frame.t.z + detail.y * frame.b.z + detail.z * frame.n.z});
}

// The detail normal a world normal is in a frame: its components along t, b and n,
// normalized, with z kept ≥ kMinDetailZ (a relief normal facing away from the macro surface is
// a measurement's error, not a surface).
inline constexpr double kMinDetailZ = 0.05;

template <typename T>
Vec3<T> detailNormalIn(const TangentFrame<T>& frame, const Vec3<T>& normal) {
    using std::sqrt;
    Vec3<T> d{dot(normal, frame.t), dot(normal, frame.b), dot(normal, frame.n)};
    const T tangential = sqrt(d.x * d.x + d.y * d.y);
    const T length = sqrt(tangential * tangential + d.z * d.z);
    if (!(length > T(0))) {
        return {0, 0, 1};
    }
    d = {d.x / length, d.y / length, d.z / length};
    if (d.z < T(kMinDetailZ)) {
        // Tilted as far as allowed, in the same direction.
        const T side = sqrt(T(1) - T(kMinDetailZ) * T(kMinDetailZ));
        const T s = tangential > T(0) ? side * length / tangential : T(0);
        d = {d.x * s, d.y * s, T(kMinDetailZ)};
    }
    return d;
}

// A detail normal as stored (the bundle and texture maps keep x and y; z ≥ 0 follows):
// z = √(1 − x² − y²), with x, y scaled back onto the unit disc when they leave it.
template <typename T>
Vec3<T> detailNormalFromXy(T x, T y) {
    using std::sqrt;
    const T r2 = x * x + y * y;
    if (r2 > T(1)) {
        const T s = T(1) / sqrt(r2);
        return {x * s, y * s, T(0)};
    }
    return {x, y, sqrt(std::max(T(1) - r2, T(0)))};
}

}  // namespace vpe::proto
