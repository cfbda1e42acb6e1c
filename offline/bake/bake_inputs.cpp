// SPDX-License-Identifier: MIT
#include "vpe/bake/bake_inputs.h"

#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/bundle_format.h"
#include "vpe/proto/detail_normal.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::bake {

CoefficientTexture readCoefficientTexture(const std::filesystem::path& model) {
    ModelReader reader(model);
    const ModelInfo& info = reader.info();
    CoefficientTexture texture;
    texture.width = info.width;
    texture.height = info.height;
    texture.harmonics = info.harmonics;
    texture.lambda = info.lambda;
    texture.tilesU = info.tilesU;
    const int k = proto::coefficientCount(info.harmonics);
    const std::size_t perTexel = 3 * static_cast<std::size_t>(k);
    const std::size_t texels = static_cast<std::size_t>(info.width) * info.height;
    texture.values.assign(texels * perTexel, 0.0f);
    texture.valid.assign(texels, 0);
    if (info.detailNormals) {
        texture.detailNormals.assign(texels * 2, 0.0f);
    }
    constexpr int kBand = 64;
    ModelRows rows;
    for (int row = 0; row < info.height; row += kBand) {
        const int count = std::min(kBand, info.height - row);
        reader.readRows(row, count, rows);
        for (int r = 0; r < count; ++r) {
            for (int x = 0; x < info.width; ++x) {
                const std::size_t t = static_cast<std::size_t>(row + r) * info.width + x;
                if (!rows.valid[rows.pixel(r, x)]) {
                    continue;
                }
                texture.valid[t] = 1;
                if (!texture.detailNormals.empty()) {
                    // Stored as x and y (z ≥ 0 follows): scaled onto the unit disc if rounding
                    // put them a hair outside.
                    const proto::Vec3f d = proto::detailNormalFromXy(
                        rows.detail[rows.pixel(r, x) * 3], rows.detail[rows.pixel(r, x) * 3 + 1]);
                    texture.detailNormals[2 * t] = d.x;
                    texture.detailNormals[2 * t + 1] = d.y;
                }
                for (int c = 0; c < 3; ++c) {
                    const float* coefficients = rows.coefficientsAt(r, x, c);
                    for (int i = 0; i < k; ++i) {
                        texture.values[t * perTexel + static_cast<std::size_t>(
                                                          proto::bundleCoefficientIndex(i, c))] =
                            coefficients[i];
                    }
                }
            }
        }
    }
    return texture;
}

BundleMesh toBundleMesh(const scene::ScreenMesh& mesh) {
    BundleMesh out;
    out.positions.reserve(mesh.positions.size() * 3);
    out.normals.reserve(mesh.normals.size() * 3);
    out.uvs.reserve(mesh.uvs.size() * 2);
    for (const auto& p : mesh.positions) {
        out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
    }
    for (const auto& n : mesh.normals) {
        out.normals.insert(out.normals.end(), {n.x, n.y, n.z});
    }
    for (const auto& uv : mesh.uvs) {
        out.uvs.insert(out.uvs.end(), {uv.x, 1.0f - uv.y});  // OBJ's v up → rows from the top
    }
    out.indices = mesh.indices;
    return out;
}

proto::ProjectorCalibration toBundleProjector(const scene::ProjectorCalibration& projector) {
    proto::ProjectorCalibration out;
    out.width = static_cast<std::uint32_t>(projector.width);
    out.height = static_cast<std::uint32_t>(projector.height);
    out.intrinsics = projector.K;
    out.distortion = projector.distortion;
    out.rotation = projector.R;
    out.translation = projector.T;
    return out;
}

proto::ResponseCurves toBundleResponse(const scene::ResponseInput& response, int samples) {
    proto::ResponseCurves out;
    if (response.isGamma()) {
        out.kind = proto::ResponseKind::kGamma;
        for (int c = 0; c < 3; ++c) {
            out.gamma[static_cast<std::size_t>(c)] =
                static_cast<float>(response.exponents()[static_cast<std::size_t>(c)]);
        }
        return out;
    }
    out.kind = proto::ResponseKind::kCurve;
    for (int c = 0; c < 3; ++c) {
        std::vector<float>& curve = out.curve[static_cast<std::size_t>(c)];
        curve.resize(static_cast<std::size_t>(samples));
        for (int i = 0; i < samples; ++i) {
            curve[static_cast<std::size_t>(i)] =
                static_cast<float>(response.output(c, static_cast<double>(i) / (samples - 1)));
        }
    }
    return out;
}

}  // namespace vpe::bake
