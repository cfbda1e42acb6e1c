// SPDX-License-Identifier: MIT
// The small vector types of the renderer's plain-data inputs: proto's Vec3, and a Vec2.
#pragma once

#include "vpe/proto/reflection_geometry.h"

namespace vpe::renderer {

using Vec3d = proto::Vec3<double>;
using Vec3f = proto::Vec3<float>;

template <typename T>
struct Vec2 {
    T x{}, y{};
};
using Vec2d = Vec2<double>;
using Vec2f = Vec2<float>;

}  // namespace vpe::renderer
