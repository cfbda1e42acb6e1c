// SPDX-License-Identifier: MIT
// Scenes made by code for the CPU renderer's tests.
#include "test_scenes.h"

#include <cmath>

namespace vpe::renderer::testing {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kVaseHeight = 0.15;

double vaseSlope(double y) {
    return 0.015 * 2 * kPi / kVaseHeight * std::cos(2 * kPi * y / kVaseHeight) + 0.01 / kVaseHeight;
}

std::vector<float> coefficientMap(int harmonics, int width, int height,
                                  const CoefficientFunction& value) {
    const int perChannel = 2 * harmonics + 2;
    std::vector<float> map;
    map.reserve(static_cast<std::size_t>(width * height * 3 * perChannel));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int k = 0; k < perChannel; ++k) {
                for (int c = 0; c < 3; ++c) {
                    map.push_back(static_cast<float>(value(x, y, k, c)));
                }
            }
        }
    }
    return map;
}

}  // namespace

OwnedMesh makePlaneMesh(double depth, double halfSize, int cells) {
    OwnedMesh mesh;
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            const double u = static_cast<double>(i) / cells, v = static_cast<double>(j) / cells;
            mesh.positions.push_back({static_cast<float>((2 * u - 1) * halfSize),
                                      static_cast<float>((2 * v - 1) * halfSize),
                                      static_cast<float>(depth)});
            mesh.normals.push_back({0, 0, -1});
            mesh.uvs.push_back({static_cast<float>(u), static_cast<float>(v)});
        }
    }
    const auto index = [cells](int i, int j) {
        return static_cast<std::uint32_t>(j * (cells + 1) + i);
    };
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            mesh.indices.insert(mesh.indices.end(),
                                {index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j),
                                 index(i + 1, j + 1), index(i, j + 1)});
        }
    }
    return mesh;
}

double vaseRadius(double y) {
    return 0.05 + 0.015 * std::sin(2 * kPi * y / kVaseHeight) + 0.01 * y / kVaseHeight;
}

proto::PinholeCamera centredPinhole(int width, int height, double focal) {
    proto::PinholeCamera camera;
    camera.width = width;
    camera.height = height;
    camera.K = {focal, 0, 0.5 * (width - 1), 0, focal, 0.5 * (height - 1), 0, 0, 1};
    return camera;
}

OwnedMesh makeVaseMesh(int segments, int rings) {
    OwnedMesh mesh;
    for (int j = 0; j <= rings; ++j) {
        const double v = static_cast<double>(j) / rings;
        const double y = v * kVaseHeight;
        const double r = vaseRadius(y);
        const double slope = vaseSlope(y);
        const double norm = std::sqrt(1 + slope * slope);
        for (int i = 0; i <= segments; ++i) {
            const double u = static_cast<double>(i) / segments;
            // φ measured so that u = 0.5 faces +z: direction (−sin 2πu, 0, −cos 2πu).
            const double s = -std::sin(2 * kPi * u), c = -std::cos(2 * kPi * u);
            mesh.positions.push_back(
                {static_cast<float>(r * s), static_cast<float>(y), static_cast<float>(r * c)});
            mesh.normals.push_back({static_cast<float>(s / norm), static_cast<float>(-slope / norm),
                                    static_cast<float>(c / norm)});
            mesh.uvs.push_back({static_cast<float>(u), static_cast<float>(v)});
        }
    }
    const auto index = [segments](int i, int j) {
        return static_cast<std::uint32_t>(j * (segments + 1) + i);
    };
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < segments; ++i) {
            mesh.indices.insert(mesh.indices.end(),
                                {index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j),
                                 index(i + 1, j + 1), index(i, j + 1)});
        }
    }
    return mesh;
}

MaterialTextures OwnedMaterial::view() const {
    MaterialTextures textures;
    textures.harmonics = harmonics;
    textures.width = width;
    textures.height = height;
    for (std::size_t r = 0; r < coefficients.size(); ++r) {
        textures.regions.push_back({coefficients[r], weights[r], {}});
    }
    return textures;
}

OwnedMaterial makeMaterial(int harmonics, int width, int height, const CoefficientFunction& value) {
    OwnedMaterial material;
    material.harmonics = harmonics;
    material.width = width;
    material.height = height;
    material.coefficients.push_back(coefficientMap(harmonics, width, height, value));
    material.weights.emplace_back();
    return material;
}

void addRegion(OwnedMaterial& material, const CoefficientFunction& value,
               const std::function<double(int x, int y)>& weight) {
    material.coefficients.push_back(
        coefficientMap(material.harmonics, material.width, material.height, value));
    std::vector<float> weights;
    for (int y = 0; y < material.height; ++y) {
        for (int x = 0; x < material.width; ++x) {
            weights.push_back(static_cast<float>(weight(x, y)));
        }
    }
    material.weights.push_back(std::move(weights));
}

}  // namespace vpe::renderer::testing
