// SPDX-License-Identifier: MIT
// SurfacePoint: what a ray hit — position, shading normal, texture coordinate.
#pragma once

#include <cstdint>

#include "vpe/renderer/cpu/ray_caster.h"
#include "vpe/renderer/cpu/render_mesh.h"

namespace vpe::renderer {

struct SurfacePoint {
    Vec3d position;         // origin + t·direction, object frame, metres
    Vec3d normal;           // shading normal, unit, on the side the ray came from
    Vec3d geometricNormal;  // the triangle's plane normal, unit, on the side the ray came from
    Vec2d uv;               // interpolated texture coordinate (OBJ / GL: v up)
    // ∂X/∂u and ∂X/∂v of the hit triangle (metres per unit of uv; v up): the directions a
    // relief's tangent frame is built from (proto/detail_normal.h). Zero when the triangle's
    // uvs are degenerate.
    Vec3d tangentU, tangentV;
    std::uint32_t triangle = 0;
};

// The surface is two-sided: the shading normal is the normalized barycentric interpolation of
// the vertex normals (the geometric normal where those cancel out), negated when the ray hit
// the back of the surface. The back is decided by the geometry, not the interpolated normal:
// the triangle's plane normal, oriented to agree with the vertex normals, faces away from the
// ray (n_g·direction > 0). So a grazing ray at a silhouette may leave the shading normal
// slightly facing away (n·(−direction) < 0), as on a GPU; the lighting clamps it.
SurfacePoint surfacePoint(const RenderMesh& mesh, const Vec3d& origin, const Vec3d& direction,
                          const RayHit& hit);

}  // namespace vpe::renderer
