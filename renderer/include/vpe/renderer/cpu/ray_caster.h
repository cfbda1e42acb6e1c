// SPDX-License-Identifier: MIT
// RayCaster: exact ray–mesh intersection through a bounding volume hierarchy, in double
// precision — how the CPU reference finds what every pixel sees.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "vpe/renderer/cpu/render_mesh.h"

namespace vpe::renderer {

// A hit at origin + t·direction on triangle `triangle` (index into the mesh's triangles), with
// barycentric coordinates (1 − b1 − b2, b1, b2) of its three vertices, each clamped to ≥ 0.
struct RayHit {
    std::uint32_t triangle = 0;
    double t = 0;
    double b1 = 0, b2 = 0;
};

class RayCaster {
public:
    // Copies the triangles (in double) and builds the hierarchy: median splits of triangle
    // centroids along the widest axis, at most 4 triangles per leaf. The mesh must pass
    // checkRenderMesh; it is not referenced afterwards.
    explicit RayCaster(const RenderMesh& mesh);

    // The nearest hit with t in (tMin, tMax), or nothing. Direction need not be unit length.
    // Triangles are two-sided. A ray through a shared edge hits (barycentrics may be
    // 1e-9 outside a triangle), so closed meshes have no cracks; among hits at the same t the
    // first in traversal order wins, which depends only on the ray (deterministic).
    std::optional<RayHit> closestHit(const Vec3d& origin, const Vec3d& direction, double tMin = 0.0,
                                     double tMax = std::numeric_limits<double>::infinity()) const;
    // Whether any triangle is hit with t in (tMin, tMax).
    bool anyHit(const Vec3d& origin, const Vec3d& direction, double tMin, double tMax) const;

    std::size_t nodeCount() const { return nodes_.size(); }

private:
    struct Node {
        double lower[3], upper[3];
        std::uint32_t first;  // inner node: index of the left child (right = first + 1)
        std::uint32_t count;  // leaf: triangles [first, first + count) of triangles_; 0 inner
    };
    struct Triangle {
        Vec3d v0, e1, e2;  // v1 = v0 + e1, v2 = v0 + e2
        std::uint32_t id;
    };

    template <bool kAnyHit>
    std::optional<RayHit> traverse(const Vec3d& origin, const Vec3d& direction, double tMin,
                                   double tMax) const;

    std::vector<Node> nodes_;
    std::vector<Triangle> triangles_;
};

}  // namespace vpe::renderer
