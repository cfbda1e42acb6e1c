// SPDX-License-Identifier: MIT
// The small vector types of the renderer's plain-data inputs: proto's (vector_types.h), by
// their short names.
#pragma once

#include "vpe/proto/reflection_geometry.h"
#include "vpe/proto/vector_types.h"

namespace vpe::renderer {

using Vec2d = proto::Vec2d;
using Vec2f = proto::Vec2f;
using Vec3d = proto::Vec3d;
using Vec3f = proto::Vec3f;

}  // namespace vpe::renderer
