// SPDX-License-Identifier: MIT
// RayCaster: a median-split BVH over the mesh's triangles, Möller–Trumbore in double.
#include "vpe/renderer/cpu/ray_caster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "vector_math.h"

namespace vpe::renderer {

namespace {

constexpr std::uint32_t kMaxLeafTriangles = 4;
// Barycentric slack: a ray through a shared edge hits at least one of its triangles despite
// rounding. Grows each triangle by ~1e-9 of its size (1e-12 m for a 1 mm triangle).
constexpr double kBarycentricSlack = 1e-9;
// Relative growth of node boxes, so that rounding in the slab test never culls a hit.
constexpr double kBoxSlack = 1e-9;
constexpr int kMaxDepth = 64;

struct Bounds {
    std::array<double, 3> lower{std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::infinity()};
    std::array<double, 3> upper{-std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity()};

    void grow(const Vec3d& p) {
        const double v[3] = {p.x, p.y, p.z};
        for (std::size_t a = 0; a < 3; ++a) {
            lower[a] = std::min(lower[a], v[a]);
            upper[a] = std::max(upper[a], v[a]);
        }
    }
};

double component(const Vec3d& v, std::size_t axis) {
    return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

}  // namespace

RayCaster::RayCaster(const RenderMesh& mesh) {
    const std::size_t count = mesh.triangleCount();
    if (count == 0 || count > std::numeric_limits<std::uint32_t>::max() / 2) {
        throw std::invalid_argument("ray caster: the mesh has no triangles, or too many");
    }
    std::vector<Triangle> source(count);
    std::vector<Vec3d> centroids(count);
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3d v0 = toDouble(mesh.positions[mesh.indices[3 * i]]);
        const Vec3d v1 = toDouble(mesh.positions[mesh.indices[3 * i + 1]]);
        const Vec3d v2 = toDouble(mesh.positions[mesh.indices[3 * i + 2]]);
        source[i] = {v0, v1 - v0, v2 - v0, static_cast<std::uint32_t>(i)};
        centroids[i] = (1.0 / 3.0) * (v0 + v1 + v2);
    }
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    nodes_.reserve(2 * count);

    // Iterative build: each entry is a node to fill with triangles order[begin, end).
    struct Task {
        std::uint32_t node, begin, end;
    };
    std::vector<Task> tasks{{0, 0, static_cast<std::uint32_t>(count)}};
    nodes_.push_back({});
    while (!tasks.empty()) {
        const Task task = tasks.back();
        tasks.pop_back();
        Bounds bounds, centroidBounds;
        for (std::uint32_t i = task.begin; i < task.end; ++i) {
            const Triangle& t = source[order[i]];
            bounds.grow(t.v0);
            bounds.grow(t.v0 + t.e1);
            bounds.grow(t.v0 + t.e2);
            centroidBounds.grow(centroids[order[i]]);
        }
        Node& node = nodes_[task.node];
        for (std::size_t a = 0; a < 3; ++a) {
            const double slack =
                kBoxSlack * (bounds.upper[a] - bounds.lower[a] + std::abs(bounds.upper[a]) +
                             std::abs(bounds.lower[a]));
            node.lower[a] = bounds.lower[a] - slack;
            node.upper[a] = bounds.upper[a] + slack;
        }
        std::size_t axis = 0;
        for (std::size_t a = 1; a < 3; ++a) {
            if (centroidBounds.upper[a] - centroidBounds.lower[a] >
                centroidBounds.upper[axis] - centroidBounds.lower[axis]) {
                axis = a;
            }
        }
        const std::uint32_t n = task.end - task.begin;
        if (n <= kMaxLeafTriangles || !(centroidBounds.upper[axis] > centroidBounds.lower[axis])) {
            node.first = task.begin;
            node.count = n;
            continue;
        }
        const std::uint32_t middle = task.begin + n / 2;
        std::nth_element(order.begin() + task.begin, order.begin() + middle,
                         order.begin() + task.end, [&](std::uint32_t a, std::uint32_t b) {
                             const double ca = component(centroids[a], axis);
                             const double cb = component(centroids[b], axis);
                             return ca < cb || (ca == cb && a < b);
                         });
        const auto left = static_cast<std::uint32_t>(nodes_.size());
        node.first = left;
        node.count = 0;
        nodes_.push_back({});  // invalidates `node`
        nodes_.push_back({});
        tasks.push_back({left, task.begin, middle});
        tasks.push_back({left + 1, middle, task.end});
    }
    triangles_.reserve(count);
    for (const std::uint32_t i : order) {
        triangles_.push_back(source[i]);
    }
}

template <bool kAnyHit>
std::optional<RayHit> RayCaster::traverse(const Vec3d& origin, const Vec3d& direction, double tMin,
                                          double tMax) const {
    // A zero component would make 0·∞ = NaN in the slab test when the origin lies on a slab.
    const auto inverse = [](double d) { return 1.0 / (d == 0.0 ? 1e-300 : d); };
    const double o[3] = {origin.x, origin.y, origin.z};
    const double inv[3] = {inverse(direction.x), inverse(direction.y), inverse(direction.z)};

    const auto enter = [&](const Node& node, double best) {
        double near = tMin, far = best;
        for (int a = 0; a < 3; ++a) {
            double t0 = (node.lower[a] - o[a]) * inv[a];
            double t1 = (node.upper[a] - o[a]) * inv[a];
            if (t0 > t1) {
                std::swap(t0, t1);
            }
            near = std::max(near, t0);
            far = std::min(far, t1);
        }
        return near <= far ? near : std::numeric_limits<double>::infinity();
    };

    std::optional<RayHit> result;
    double best = tMax;
    std::uint32_t stack[kMaxDepth * 2];
    int top = 0;
    if (enter(nodes_[0], best) == std::numeric_limits<double>::infinity()) {
        return result;
    }
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[stack[--top]];
        if (node.count > 0) {
            for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                const Triangle& tri = triangles_[i];
                const Vec3d p = cross(direction, tri.e2);
                const double det = proto::dot(tri.e1, p);
                if (det == 0.0) {
                    continue;
                }
                const double invDet = 1.0 / det;
                const Vec3d s = origin - tri.v0;
                const double b1 = proto::dot(s, p) * invDet;
                if (b1 < -kBarycentricSlack || b1 > 1 + kBarycentricSlack) {
                    continue;
                }
                const Vec3d q = cross(s, tri.e1);
                const double b2 = proto::dot(direction, q) * invDet;
                if (b2 < -kBarycentricSlack || b1 + b2 > 1 + kBarycentricSlack) {
                    continue;
                }
                const double t = proto::dot(tri.e2, q) * invDet;
                if (!(t > tMin && t < best)) {
                    continue;
                }
                best = t;
                result = RayHit{tri.id, t, b1, b2};
                if constexpr (kAnyHit) {
                    return result;
                }
            }
            continue;
        }
        const double nearLeft = enter(nodes_[node.first], best);
        const double nearRight = enter(nodes_[node.first + 1], best);
        const double inf = std::numeric_limits<double>::infinity();
        // Push the farther child first so the nearer one is visited first. The stack cannot
        // overflow: it holds at most one pending sibling per level, and median splits keep
        // the depth near log2(triangles).
        if (nearLeft <= nearRight) {
            if (nearRight != inf) {
                stack[top++] = node.first + 1;
            }
            if (nearLeft != inf) {
                stack[top++] = node.first;
            }
        } else {
            if (nearLeft != inf) {
                stack[top++] = node.first;
            }
            stack[top++] = node.first + 1;
        }
    }
    return result;
}

std::optional<RayHit> RayCaster::closestHit(const Vec3d& origin, const Vec3d& direction,
                                            double tMin, double tMax) const {
    std::optional<RayHit> hit = traverse<false>(origin, direction, tMin, tMax);
    if (hit) {
        // Barycentrics within the slack are moved onto the triangle.
        hit->b1 = std::clamp(hit->b1, 0.0, 1.0);
        hit->b2 = std::clamp(hit->b2, 0.0, 1.0 - hit->b1);
    }
    return hit;
}

bool RayCaster::anyHit(const Vec3d& origin, const Vec3d& direction, double tMin,
                       double tMax) const {
    return traverse<true>(origin, direction, tMin, tMax).has_value();
}

}  // namespace vpe::renderer
