// SPDX-License-Identifier: MIT
// Vec2 and Vec3: the small vectors of proto's contracts, defined once for offline/, renderer/
// and firmware/ (the renderer's and offline's Vec2d, Vec3f, ... are aliases of these).
#pragma once

#include <cmath>

namespace vpe::proto {

template <typename T>
struct Vec2 {
    T x{}, y{};
};

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};
};

using Vec2d = Vec2<double>;
using Vec2f = Vec2<float>;
using Vec3d = Vec3<double>;
using Vec3f = Vec3<float>;

template <typename T>
inline T dot(const Vec3<T>& a, const Vec3<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <typename T>
inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename T>
inline Vec3<T> normalized(const Vec3<T>& v) {
    using std::sqrt;
    const T length = sqrt(dot(v, v));
    return {v.x / length, v.y / length, v.z / length};
}

}  // namespace vpe::proto
