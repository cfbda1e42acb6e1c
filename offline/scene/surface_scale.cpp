// SPDX-License-Identifier: MIT
// Surface lengths of the texture's axes, per triangle, and what follows from them.
#include "vpe/scene/surface_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <tuple>

#include "vpe/common/input_error.h"

namespace vpe::scene {

namespace {

using Vec3 = proto::Vec3d;
double wide(float x) {
    return static_cast<double>(x);
}
Vec3 minus(const Vec3f& a, const Vec3f& b) {
    return {wide(a.x) - wide(b.x), wide(a.y) - wide(b.y), wide(a.z) - wide(b.z)};
}
Vec3 combine(const Vec3& a, double s, const Vec3& b, double t) {
    return {a.x * s + b.x * t, a.y * s + b.y * t, a.z * s + b.z * t};
}
double length(const Vec3& a) {
    return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

// Within this of 0 or 1 a texture coordinate is on the texture's edge.
constexpr float kEdge = 1e-4f;

// Seam pairs: a vertex at u ≈ 0 and one at u ≈ 1 with the same position and v. Positions are
// compared exactly as stored (a wrapped mesh duplicates its seam vertices), v to kEdge.
std::size_t countSeamPairs(const ScreenMesh& mesh) {
    using Key = std::tuple<float, float, float>;
    std::multimap<Key, float> right;  // position → v of the vertices at u ≈ 1
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        if (mesh.uvs[i].x >= 1.0f - kEdge) {
            const Vec3f& p = mesh.positions[i];
            right.emplace(Key{p.x, p.y, p.z}, mesh.uvs[i].y);
        }
    }
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
        if (mesh.uvs[i].x > kEdge) {
            continue;
        }
        const Vec3f& p = mesh.positions[i];
        const auto [begin, end] = right.equal_range(Key{p.x, p.y, p.z});
        for (auto it = begin; it != end; ++it) {
            if (std::fabs(it->second - mesh.uvs[i].y) <= kEdge) {
                ++pairs;
                break;
            }
        }
    }
    return pairs;
}

// The value below which `share` of the total weight lies (weights need not be normalized).
double weightedQuantile(std::vector<std::pair<double, double>> valueWeight, double share) {
    std::sort(valueWeight.begin(), valueWeight.end());
    double total = 0;
    for (const auto& [value, weight] : valueWeight) {
        total += weight;
    }
    double running = 0;
    for (const auto& [value, weight] : valueWeight) {
        running += weight;
        if (running >= share * total) {
            return value;
        }
    }
    return valueWeight.empty() ? 0.0 : valueWeight.back().first;
}

}  // namespace

SurfaceScale measureSurfaceScale(const ScreenMesh& mesh, const char* source) {
    SurfaceScale scale;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1],
                            c = mesh.indices[3 * t + 2];
        const Vec3 e1 = minus(mesh.positions[b], mesh.positions[a]);
        const Vec3 e2 = minus(mesh.positions[c], mesh.positions[a]);
        const double du1 = wide(mesh.uvs[b].x) - wide(mesh.uvs[a].x);
        const double dv1 = wide(mesh.uvs[b].y) - wide(mesh.uvs[a].y);
        const double du2 = wide(mesh.uvs[c].x) - wide(mesh.uvs[a].x);
        const double dv2 = wide(mesh.uvs[c].y) - wide(mesh.uvs[a].y);
        const double det = du1 * dv2 - du2 * dv1;
        const double area = 0.5 * length(proto::cross(e1, e2));
        if (std::fabs(det) < 1e-14 || !(area > 0)) {
            ++scale.flatUvTriangles;
            continue;
        }
        // p(u, v) linear over the triangle: [e1 e2] = [∂p/∂u ∂p/∂v] · [[du1 du2] [dv1 dv2]].
        const Vec3 dpdu = combine(e1, dv2 / det, e2, -dv1 / det);
        const Vec3 dpdv = combine(e2, du1 / det, e1, -du2 / det);
        TriangleScale triangle;
        triangle.area = area;
        triangle.lengthU = length(dpdu);
        triangle.lengthV = length(dpdv);
        triangle.u = (mesh.uvs[a].x + mesh.uvs[b].x + mesh.uvs[c].x) / 3.0f;
        triangle.v = (mesh.uvs[a].y + mesh.uvs[b].y + mesh.uvs[c].y) / 3.0f;
        scale.triangles.push_back(triangle);
        scale.area += area;
    }
    if (scale.triangles.empty()) {
        throw common::InputError(std::string(source) +
                                 ": no triangle's texture coordinates span an area");
    }
    scale.seamVertexPairs = countSeamPairs(mesh);
    // One shared vertex could be a coincidence of a UV atlas; a seam is an edge at least.
    scale.wrapsU = scale.seamVertexPairs >= 2;
    return scale;
}

TexelStretch measureTexelStretch(const SurfaceScale& scale, int width, int height) {
    TexelStretch stretch;
    std::vector<std::pair<double, double>> values;  // (stretch, area)
    values.reserve(scale.triangles.size());
    double sum = 0, logU = 0, logV = 0;
    stretch.worst = 0;
    for (const TriangleScale& t : scale.triangles) {
        const double u = t.lengthU / width, v = t.lengthV / height;
        const double s = std::max(u, v) / std::min(u, v);
        values.emplace_back(s, t.area);
        sum += s * t.area;
        logU += std::log(u) * t.area;
        logV += std::log(v) * t.area;
        if (s > stretch.worst) {
            stretch.worst = s;
            stretch.worstU = t.u;
            stretch.worstV = t.v;
        }
    }
    stretch.mean = sum / scale.area;
    stretch.median = weightedQuantile(values, 0.5);
    stretch.p95 = weightedQuantile(std::move(values), 0.95);
    stretch.texelUMm = 1000.0 * std::exp(logU / scale.area);
    stretch.texelVMm = 1000.0 * std::exp(logV / scale.area);
    return stretch;
}

AutoTextureSize chooseTextureSize(const SurfaceScale& scale, double texelMm, int maxSide) {
    if (!(texelMm > 0) || !std::isfinite(texelMm)) {
        throw common::InputError("texel size must be a positive number of millimetres");
    }
    // Area-weighted mean of log |∂p/∂u|: the size whose geometric-mean texel is texelMm long
    // along u; likewise v. This also minimizes the area-weighted mean of log² stretch.
    double logU = 0, logV = 0;
    for (const TriangleScale& t : scale.triangles) {
        logU += std::log(t.lengthU) * t.area;
        logV += std::log(t.lengthV) * t.area;
    }
    const double metres = texelMm / 1000.0;
    const double width = std::exp(logU / scale.area) / metres;
    const double height = std::exp(logV / scale.area) / metres;
    char text[160];
    std::snprintf(text, sizeof text, "%.0fx%.0f texels at %.4g mm", width, height, texelMm);
    if (width > maxSide || height > maxSide) {
        throw common::InputError(
            "--size auto: the screen object needs " + std::string(text) + ", more than the " +
            std::to_string(maxSide) +
            " a side may have (the "
            "device's texture limit); give a coarser --texel-mm or a smaller object");
    }
    if (width < 8 || height < 8) {
        throw common::InputError(
            "--size auto: the screen object needs only " + std::string(text) +
            ", fewer than 8 a side; is --texel-mm (or the mesh's scale) right?");
    }
    return {std::max(8, static_cast<int>(std::lround(width))),
            std::max(8, static_cast<int>(std::lround(height)))};
}

}  // namespace vpe::scene
