// SPDX-License-Identifier: MIT
// surfacePoint: interpolation at a ray hit, and the side of the surface the ray came from.
#include "vpe/renderer/cpu/surface_point.h"

#include <cmath>

#include "vector_math.h"

namespace vpe::renderer {

SurfacePoint surfacePoint(const RenderMesh& mesh, const Vec3d& origin, const Vec3d& direction,
                          const RayHit& hit) {
    const std::size_t base = 3 * static_cast<std::size_t>(hit.triangle);
    const std::uint32_t i0 = mesh.indices[base], i1 = mesh.indices[base + 1],
                        i2 = mesh.indices[base + 2];
    const double b0 = 1.0 - hit.b1 - hit.b2;

    SurfacePoint point;
    point.triangle = hit.triangle;
    point.position = origin + hit.t * direction;

    const Vec3d p0 = toDouble(mesh.positions[i0]);
    Vec3d geometric = cross(toDouble(mesh.positions[i1]) - p0, toDouble(mesh.positions[i2]) - p0);
    const Vec3d interpolated = b0 * toDouble(mesh.normals[i0]) +
                               hit.b1 * toDouble(mesh.normals[i1]) +
                               hit.b2 * toDouble(mesh.normals[i2]);
    const double geometricLength = length(geometric);
    geometric = geometricLength > 0 ? (1.0 / geometricLength) * geometric : Vec3d{0, 0, 1};
    const double interpolatedLength = length(interpolated);
    Vec3d normal = interpolatedLength > 0 ? (1.0 / interpolatedLength) * interpolated : geometric;
    // The plane normal on the vertex normals' side, whatever the winding.
    if (proto::dot(geometric, normal) < 0) {
        geometric = -geometric;
    }
    // The back of the surface: both normals turn to the ray's side.
    if (proto::dot(geometric, direction) > 0) {
        geometric = -geometric;
        normal = -normal;
    }
    point.normal = normal;
    point.geometricNormal = geometric;

    const auto& t0 = mesh.uvs[i0];
    const auto& t1 = mesh.uvs[i1];
    const auto& t2 = mesh.uvs[i2];
    point.uv = {b0 * static_cast<double>(t0.x) + hit.b1 * static_cast<double>(t1.x) +
                    hit.b2 * static_cast<double>(t2.x),
                b0 * static_cast<double>(t0.y) + hit.b1 * static_cast<double>(t1.y) +
                    hit.b2 * static_cast<double>(t2.y)};

    // The triangle's position as a linear function of uv: e1 = ∂X/∂u·Δu1 + ∂X/∂v·Δv1, likewise
    // e2; solved for the two derivatives (constant over the triangle).
    const Vec3d e1 = toDouble(mesh.positions[i1]) - p0, e2 = toDouble(mesh.positions[i2]) - p0;
    const double du1 = static_cast<double>(t1.x) - static_cast<double>(t0.x),
                 dv1 = static_cast<double>(t1.y) - static_cast<double>(t0.y),
                 du2 = static_cast<double>(t2.x) - static_cast<double>(t0.x),
                 dv2 = static_cast<double>(t2.y) - static_cast<double>(t0.y);
    const double determinant = du1 * dv2 - du2 * dv1;
    if (determinant != 0 && std::isfinite(1.0 / determinant)) {
        const double inverse = 1.0 / determinant;
        point.tangentU = inverse * (dv2 * e1 - dv1 * e2);
        point.tangentV = inverse * (du1 * e2 - du2 * e1);
    }
    return point;
}

}  // namespace vpe::renderer
