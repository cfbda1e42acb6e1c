// SPDX-License-Identifier: MIT
#include "benchmark_bundle.h"

#include <cmath>

namespace vpe::benchmarks {

bake::BundleMesh planeMesh(int cells, float width, float height, float normalZ) {
    bake::BundleMesh mesh;
    const int n = cells + 1;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const float u = static_cast<float>(x) / static_cast<float>(cells);
            const float v = static_cast<float>(y) / static_cast<float>(cells);
            mesh.positions.insert(mesh.positions.end(),
                                  {width * (u - 0.5f), height * (v - 0.5f), 0.0f});
            mesh.normals.insert(mesh.normals.end(), {0.0f, 0.0f, normalZ});
            mesh.uvs.insert(mesh.uvs.end(), {u, v});
        }
    }
    for (int y = 0; y < cells; ++y) {
        for (int x = 0; x < cells; ++x) {
            const auto i = static_cast<std::uint32_t>(y * n + x);
            const auto below = i + static_cast<std::uint32_t>(n);
            mesh.indices.insert(mesh.indices.end(), {i, below, i + 1, i + 1, below, below + 1});
        }
    }
    return mesh;
}

proto::ProjectorCalibration benchmarkProjector() {
    proto::ProjectorCalibration projector;
    projector.width = 1920;
    projector.height = 1080;
    projector.intrinsics = {2000, 0, 960, 0, 2000, 540, 0, 0, 1};
    projector.rotation = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    projector.translation = {0, 0, 1.5};
    return projector;
}

bake::WeightPreset stripesPreset(int size) {
    const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
    bake::WeightPreset preset;
    preset.name = "stripes";
    preset.alpha.resize(2 * texels);
    for (std::size_t t = 0; t < texels; ++t) {
        const float a =
            0.5f + 0.5f * std::sin(static_cast<float>(t % static_cast<std::size_t>(size)) / 40.0f);
        preset.alpha[t] = a;
        preset.alpha[texels + t] = 1.0f - a;
    }
    return preset;
}

void usePaperModel(bake::BundleContents& contents, int size) {
    contents.model.harmonics = 10;
    contents.model.lambda = 3.14;
    contents.textureWidth = contents.textureHeight = size;
}

bake::BundleRegion lowRankRegion(int index, int rank) {
    bake::BundleRegion region;
    region.name = index == 0 ? "clay" : "glaze";
    region.coefficients.encoding = proto::CoefficientEncoding::kLowRank;
    region.coefficients.rank = rank;
    return region;
}

}  // namespace vpe::benchmarks
