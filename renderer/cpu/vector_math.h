// SPDX-License-Identifier: MIT
// Vector arithmetic on proto's Vec3<double>, private to the CPU renderer.
#pragma once

#include <cmath>

#include "vpe/renderer/cpu/vector_types.h"

namespace vpe::renderer {

inline Vec3d operator+(const Vec3d& a, const Vec3d& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3d operator-(const Vec3d& a, const Vec3d& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3d operator-(const Vec3d& a) {
    return {-a.x, -a.y, -a.z};
}
inline Vec3d operator*(double s, const Vec3d& a) {
    return {s * a.x, s * a.y, s * a.z};
}
using proto::cross;
inline double length(const Vec3d& a) {
    return std::sqrt(proto::dot(a, a));
}
inline Vec3d toDouble(const Vec3f& a) {
    return {static_cast<double>(a.x), static_cast<double>(a.y), static_cast<double>(a.z)};
}
inline bool isFinite(const Vec3d& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

}  // namespace vpe::renderer
