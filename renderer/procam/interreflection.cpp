// SPDX-License-Identifier: MIT
// One bounce of radiosity between texture-space patches of the object.
#include "interreflection.h"

#include <algorithm>
#include <cmath>

#include "vpe/renderer/cpu/parallel_rows.h"

#include "vector_math.h"

namespace vpe::renderer::procam {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Points are lifted this far off the surface (metres) before shadow tests: far above the
// rounding of a point on a triangle, and above the sagitta of a patch's cell on a curved
// surface (0.06 mm for 5 mm cells on a 50 mm radius), far below the object's features.
constexpr double kLift = 2e-4;

}  // namespace

Interreflection::Interreflection(const RenderMesh& mesh, std::uint32_t objectTriangles, int grid,
                                 const AlbedoAt& albedoAt, const ProjectorReach& reach,
                                 const RayCaster& caster, int threads)
    : grid_(grid), cellPatch_(static_cast<std::size_t>(grid) * grid, -1) {
    // Each patch's triangle, kept to place its cell's sub-samples by the same affine map.
    std::vector<std::uint32_t> patchTriangle;
    for (std::uint32_t t = 0; t < objectTriangles; ++t) {
        const std::uint32_t i[3] = {mesh.indices[3 * t], mesh.indices[3 * t + 1],
                                    mesh.indices[3 * t + 2]};
        const Vec2d uv[3] = {{mesh.uvs[i[0]].x, mesh.uvs[i[0]].y},
                             {mesh.uvs[i[1]].x, mesh.uvs[i[1]].y},
                             {mesh.uvs[i[2]].x, mesh.uvs[i[2]].y}};
        const double det =
            (uv[1].x - uv[0].x) * (uv[2].y - uv[0].y) - (uv[2].x - uv[0].x) * (uv[1].y - uv[0].y);
        if (!(std::abs(det) > 1e-14)) {
            continue;
        }
        const auto bound = [&](double a, double b, double c, bool upper) {
            const double v = (upper ? std::max({a, b, c}) : std::min({a, b, c})) * grid - 0.5;
            return std::clamp(static_cast<int>(upper ? std::floor(v) : std::ceil(v)), 0, grid - 1);
        };
        const int u0 = bound(uv[0].x, uv[1].x, uv[2].x, false);
        const int u1 = bound(uv[0].x, uv[1].x, uv[2].x, true);
        const int v0 = bound(uv[0].y, uv[1].y, uv[2].y, false);
        const int v1 = bound(uv[0].y, uv[1].y, uv[2].y, true);
        const Vec3d p[3] = {toDouble(mesh.positions[i[0]]), toDouble(mesh.positions[i[1]]),
                            toDouble(mesh.positions[i[2]])};
        const double area3d = 0.5 * length(cross(p[1] - p[0], p[2] - p[0]));
        const double areaUv = 0.5 * std::abs(det);
        for (int cv = v0; cv <= v1; ++cv) {
            for (int cu = u0; cu <= u1; ++cu) {
                const std::size_t cell = static_cast<std::size_t>(cv) * grid + cu;
                if (cellPatch_[cell] >= 0) {
                    continue;
                }
                const double u = (cu + 0.5) / grid, v = (cv + 0.5) / grid;
                const double b1 =
                    ((u - uv[0].x) * (uv[2].y - uv[0].y) - (uv[2].x - uv[0].x) * (v - uv[0].y)) /
                    det;
                const double b2 =
                    ((uv[1].x - uv[0].x) * (v - uv[0].y) - (u - uv[0].x) * (uv[1].y - uv[0].y)) /
                    det;
                const double b0 = 1 - b1 - b2;
                if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) {
                    continue;
                }
                Patch patch;
                patch.position = b0 * p[0] + b1 * p[1] + b2 * p[2];
                const Vec3d n = b0 * toDouble(mesh.normals[i[0]]) +
                                b1 * toDouble(mesh.normals[i[1]]) +
                                b2 * toDouble(mesh.normals[i[2]]);
                patch.normal = (1.0 / length(n)) * n;
                patch.area = area3d / areaUv / (static_cast<double>(grid) * grid);
                SurfacePoint point;
                point.position = patch.position;
                point.normal = patch.normal;
                point.triangle = t;
                const std::array<double, 3> albedo = albedoAt(point);
                for (std::size_t c = 0; c < 3; ++c) {
                    patch.albedoOverPi[c] = albedo[c] / kPi;
                }
                cellPatch_[cell] = static_cast<int>(patches_.size());
                patches_.push_back(patch);
                patchTriangle.push_back(t);
                // The cell's 3 × 3 sub-samples, by the triangle's affine map from uv.
                for (int sv = 0; sv < 3; ++sv) {
                    for (int su = 0; su < 3; ++su) {
                        const double su0 = (cu + (su + 0.5) / 3) / grid;
                        const double sv0 = (cv + (sv + 0.5) / 3) / grid;
                        const double c1 = ((su0 - uv[0].x) * (uv[2].y - uv[0].y) -
                                           (uv[2].x - uv[0].x) * (sv0 - uv[0].y)) /
                                          det;
                        const double c2 = ((uv[1].x - uv[0].x) * (sv0 - uv[0].y) -
                                           (su0 - uv[0].x) * (uv[1].y - uv[0].y)) /
                                          det;
                        const Vec3d x =
                            (1 - c1 - c2) * p[0] + c1 * p[1] + c2 * p[2] + kLift * patch.normal;
                        double scale = 0;
                        Vec2d pixel;
                        SubSample sample{0, 0, 0};
                        if (reach(x, patch.normal, scale, pixel)) {
                            sample = {float(pixel.x), float(pixel.y), float(scale / kSubSamples)};
                        }
                        subSamples_.push_back(sample);
                    }
                }
            }
        }
    }
    const std::size_t count = patches_.size();
    formFactors_.assign(count * count, 0.0f);
    forEachRow(static_cast<int>(count), threads, [&](int receiver) {
        const Patch& a = patches_[static_cast<std::size_t>(receiver)];
        const Vec3d from = a.position + kLift * a.normal;
        for (std::size_t j = 0; j < count; ++j) {
            if (j == static_cast<std::size_t>(receiver)) {
                continue;
            }
            const Patch& b = patches_[j];
            const Vec3d d = b.position - a.position;
            const double r2 = proto::dot(d, d);
            const double r = std::sqrt(r2);
            const double cosA = proto::dot(a.normal, d) / r;
            const double cosB = -proto::dot(b.normal, d) / r;
            if (!(cosA > 0 && cosB > 0)) {
                continue;
            }
            const Vec3d to = b.position + kLift * b.normal;
            if (caster.anyHit(from, to - from, 1e-6, 1.0 - 1e-6)) {
                continue;
            }
            formFactors_[static_cast<std::size_t>(receiver) * count + j] =
                static_cast<float>(cosA * cosB * b.area / (r2 + b.area / kPi));
        }
    });
}

std::vector<float> Interreflection::bounce(const ProjectorLight& light,
                                           const std::array<double, 3>& ambient) const {
    const std::size_t count = patches_.size();
    std::vector<float> radiance(count * 3);
    for (std::size_t j = 0; j < count; ++j) {
        double e[3] = {ambient[0], ambient[1], ambient[2]};
        for (int k = 0; k < kSubSamples; ++k) {
            const SubSample& s = subSamples_[j * kSubSamples + static_cast<std::size_t>(k)];
            if (s.scale > 0) {
                const std::array<float, 3> rgb = light.at(s.px, s.py);
                for (std::size_t c = 0; c < 3; ++c) {
                    e[c] += static_cast<double>(s.scale * rgb[c]);
                }
            }
        }
        for (std::size_t c = 0; c < 3; ++c) {
            radiance[3 * j + c] = static_cast<float>(patches_[j].albedoOverPi[c] * e[c]);
        }
    }
    std::vector<float> irradiance(count * 3, 0.0f);
    for (std::size_t i = 0; i < count; ++i) {
        const float* row = formFactors_.data() + i * count;
        float sum[3] = {0, 0, 0};
        for (std::size_t j = 0; j < count; ++j) {
            const float f = row[j];
            sum[0] += f * radiance[3 * j];
            sum[1] += f * radiance[3 * j + 1];
            sum[2] += f * radiance[3 * j + 2];
        }
        std::copy(sum, sum + 3, irradiance.begin() + std::ptrdiff_t(3 * i));
    }
    return irradiance;
}

std::array<float, 3> Interreflection::lookup(const std::vector<float>& bounce, float u,
                                             float v) const {
    const float cu = u * static_cast<float>(grid_) - 0.5f,
                cv = v * static_cast<float>(grid_) - 0.5f;
    const int u0 = static_cast<int>(std::floor(cu)), v0 = static_cast<int>(std::floor(cv));
    const float fu = cu - static_cast<float>(u0), fv = cv - static_cast<float>(v0);
    std::array<float, 3> sum{};
    float weights = 0;
    for (int k = 0; k < 4; ++k) {
        const int iu = std::clamp(u0 + (k & 1), 0, grid_ - 1);
        const int iv = std::clamp(v0 + (k >> 1), 0, grid_ - 1);
        const int patch = cellPatch_[static_cast<std::size_t>(iv) * grid_ + iu];
        if (patch < 0) {
            continue;
        }
        const float w = ((k & 1) ? fu : 1 - fu) * ((k >> 1) ? fv : 1 - fv);
        for (std::size_t c = 0; c < 3; ++c) {
            sum[c] += w * bounce[3 * static_cast<std::size_t>(patch) + c];
        }
        weights += w;
    }
    if (weights > 0) {
        for (float& value : sum) {
            value /= weights;
        }
    }
    return sum;
}

}  // namespace vpe::renderer::procam
