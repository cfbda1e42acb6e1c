// SPDX-License-Identifier: MIT
#include "vpe/bake/bake_inputs.h"

#include "vpe/proto/bundle_format.h"
#include "vpe/proto/detail_normal.h"
#include "vpe/proto/fourier_brdf.h"

namespace vpe::bake {

std::vector<float> bundleCoefficients(const model::CoefficientImage& model) {
    const int k = proto::coefficientCount(model.harmonics);
    const std::size_t perTexel = 3 * static_cast<std::size_t>(k);
    std::vector<float> values(model.valid.size() * perTexel, 0.0f);
    for (std::size_t t = 0; t < model.valid.size(); ++t) {
        if (!model.valid[t]) {
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            const float* coefficients = model.at(t) + static_cast<std::size_t>(c) * k;
            for (int i = 0; i < k; ++i) {
                values[t * perTexel + static_cast<std::size_t>(
                                          proto::bundleCoefficientIndex(i, c))] = coefficients[i];
            }
        }
    }
    return values;
}

std::vector<float> bundleDetailNormals(const model::CoefficientImage& model) {
    if (model.detail.empty()) {
        return {};
    }
    std::vector<float> xy(model.valid.size() * 2, 0.0f);
    for (std::size_t t = 0; t < model.valid.size(); ++t) {
        if (model.valid[t]) {
            // Stored as x and y (z ≥ 0 follows): scaled onto the unit disc if rounding put them
            // a hair outside.
            const proto::Vec3f d =
                proto::detailNormalFromXy(model.detail[t * 3], model.detail[t * 3 + 1]);
            xy[2 * t] = d.x;
            xy[2 * t + 1] = d.y;
        }
    }
    return xy;
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
