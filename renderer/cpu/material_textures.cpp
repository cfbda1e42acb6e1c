// SPDX-License-Identifier: MIT
// Bilinear sampling of the region maps (clamped to the edge, or wrapping in u) and the Fourier
// BRDF per channel.
#include "vpe/renderer/cpu/material_textures.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "vpe/proto/detail_normal.h"
#include "vpe/proto/reflection_geometry.h"

namespace vpe::renderer {

BilinearFootprint bilinearFootprint(int width, int height, const Vec2d& uv, bool wrapU) {
    const auto axis = [](double coordinate, int size, int& i0, int& i1, double& f) {
        double x = coordinate * size - 0.5;
        x = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, static_cast<double>(size - 1));
        i0 = static_cast<int>(std::floor(x));
        i1 = std::min(i0 + 1, size - 1);
        f = x - i0;
    };
    const auto wrappingAxis = [](double coordinate, int size, int& i0, int& i1, double& f) {
        double x = coordinate * size - 0.5;
        x = std::isfinite(x) ? x - size * std::floor(x / size) : 0.0;  // [0, size)
        i0 = std::min(static_cast<int>(std::floor(x)), size - 1);
        i1 = i0 + 1 == size ? 0 : i0 + 1;
        f = std::clamp(x - i0, 0.0, 1.0);
    };
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    double fx = 0, fy = 0;
    if (wrapU) {
        wrappingAxis(uv.x, width, x0, x1, fx);
    } else {
        axis(uv.x, width, x0, x1, fx);
    }
    axis(1.0 - uv.y, height, y0, y1, fy);
    const auto index = [width](int x, int y) {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x);
    };
    return {{index(x0, y0), index(x1, y0), index(x0, y1), index(x1, y1)},
            {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

std::string checkMaterialTextures(const MaterialTextures& material) {
    if (material.harmonics < 0 || material.harmonics > proto::kMaxHarmonics) {
        return "harmonics " + std::to_string(material.harmonics) + " is outside 0.." +
               std::to_string(proto::kMaxHarmonics);
    }
    if (material.width < 1 || material.height < 1) {
        return "size " + std::to_string(material.width) + "x" + std::to_string(material.height) +
               " is empty";
    }
    if (material.regions.empty()) {
        return "no regions";
    }
    const std::size_t texels =
        static_cast<std::size_t>(material.width) * static_cast<std::size_t>(material.height);
    const std::size_t values = texels * static_cast<std::size_t>(material.coefficientsPerTexel());
    for (std::size_t r = 0; r < material.regions.size(); ++r) {
        const auto& region = material.regions[r];
        if (region.coefficients.size() != values) {
            return "region " + std::to_string(r) +
                   " coefficients: " + std::to_string(region.coefficients.size()) +
                   " values, expected " + std::to_string(values);
        }
        if (!region.weights.empty() && region.weights.size() != texels) {
            return "region " + std::to_string(r) +
                   " weights: " + std::to_string(region.weights.size()) + " values, expected " +
                   std::to_string(texels);
        }
        if (!region.detailNormals.empty() && region.detailNormals.size() != 2 * texels) {
            return "region " + std::to_string(r) +
                   " detail normals: " + std::to_string(region.detailNormals.size()) +
                   " values, expected " + std::to_string(2 * texels);
        }
    }
    return "";
}

namespace {

// The region's weight at the footprint, bilinear in its weight map (1 without one).
double sampleRegionWeight(const MaterialRegion& region, const BilinearFootprint& taps) {
    if (region.weights.empty()) {
        return 1.0;
    }
    double weight = 0.0;
    for (int i = 0; i < 4; ++i) {
        weight += taps.weight[i] * static_cast<double>(region.weights[taps.texel[i]]);
    }
    return weight;
}

}  // namespace

void sampleMaterial(const MaterialTextures& material, const Vec2d& uv, double* coefficients) {
    const int count = material.coefficientsPerTexel();
    std::fill(coefficients, coefficients + count, 0.0);
    const BilinearFootprint taps =
        bilinearFootprint(material.width, material.height, uv, material.wrapU);
    const auto perTexel = static_cast<std::size_t>(count);
    for (const auto& region : material.regions) {
        const double regionWeight = sampleRegionWeight(region, taps);
        if (regionWeight == 0.0) {
            continue;
        }
        for (int i = 0; i < 4; ++i) {
            const double w = regionWeight * taps.weight[i];
            if (w == 0.0) {
                continue;
            }
            const float* texel = region.coefficients.data() + taps.texel[i] * perTexel;
            for (int k = 0; k < count; ++k) {
                coefficients[k] += w * static_cast<double>(texel[k]);
            }
        }
    }
}

bool hasRelief(const MaterialTextures& material) {
    return std::any_of(material.regions.begin(), material.regions.end(),
                       [](const MaterialRegion& region) { return !region.detailNormals.empty(); });
}

Vec3d sampleDetailNormal(const MaterialTextures& material, const Vec2d& uv) {
    const BilinearFootprint taps =
        bilinearFootprint(material.width, material.height, uv, material.wrapU);
    Vec3d sum{0, 0, 0};
    for (const auto& region : material.regions) {
        const double regionWeight = sampleRegionWeight(region, taps);
        if (regionWeight == 0.0) {
            continue;
        }
        Vec3d detail{0, 0, 1};
        if (!region.detailNormals.empty()) {
            double x = 0, y = 0;
            for (int i = 0; i < 4; ++i) {
                x += taps.weight[i] * static_cast<double>(region.detailNormals[2 * taps.texel[i]]);
                y += taps.weight[i] *
                     static_cast<double>(region.detailNormals[2 * taps.texel[i] + 1]);
            }
            detail = proto::detailNormalFromXy(x, y);
        }
        sum = {sum.x + regionWeight * detail.x, sum.y + regionWeight * detail.y,
               sum.z + regionWeight * detail.z};
    }
    return sum;
}

Vec3d shadingNormal(const MaterialTextures& material, const SurfacePoint& point) {
    if (!hasRelief(material)) {
        return point.normal;
    }
    const Vec3d detail = sampleDetailNormal(material, point.uv);
    if (!(detail.z > 0)) {  // no region weighs here
        return point.normal;
    }
    return proto::applyDetailNormal(
        proto::tangentFrame(point.normal, point.tangentU, point.tangentV), detail);
}

std::array<double, 3> evaluateMaterial(const double* coefficients, int harmonics,
                                       const Vec3d& normal, const Vec3d& toLight,
                                       const Vec3d& toViewer) {
    const auto angles = proto::reflectionAngles(normal, toLight, toViewer);
    const int perChannel = proto::coefficientCount(harmonics);
    std::array<double, 3> f{};
    double channel[proto::coefficientCount(proto::kMaxHarmonics)];
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < perChannel; ++k) {
            channel[k] = coefficients[3 * k + c];  // proto::bundleCoefficientIndex(k, c)
        }
        f[static_cast<std::size_t>(c)] = proto::evaluateFourierBrdf<double>(
            channel, harmonics, angles.cosThetaD, angles.cosThetaS);
    }
    return f;
}

}  // namespace vpe::renderer
