// SPDX-License-Identifier: MIT
// A small bundle's contents with every field set to something recognizable, for the writer's
// round-trip tests and `vpe info`'s: odd texture sizes, a rank that leaves layer padding, a
// composed map, presets in both α encodings, and a θs basis.
#pragma once

#include <cmath>

#include "vpe/bake/bundle_writer.h"

namespace vpe::testing {

inline bake::BundleContents sampleBundleContents() {
    bake::BundleContents c;
    c.mesh.positions = {0, 0, 0, 0.1f, 0, 0, 0, 0.1f, 0, 0.1f, 0.1f, 0.02f};
    c.mesh.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0.6f, 0.8f};
    c.mesh.uvs = {0, 0, 1, 0, 0, 1, 1, 1};
    c.mesh.indices = {0, 1, 2, 2, 1, 3};

    c.projector.width = 1280;
    c.projector.height = 800;
    c.projector.intrinsics = {1500.5, 0.25, 640.5, 0, 1498.0, 400.25, 0, 0, 1};
    c.projector.distortion = {-0.12, 0.034, 0.0011, -0.0007, 0.0005};
    const double a = 0.3;  // a rotation about x
    c.projector.rotation = {1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a)};
    c.projector.translation = {0.05, -0.1, 1.2};

    c.settings.viewerPosition = {0.0f, 0.25f, 1.75f};
    c.settings.screenAlbedo = {0.86f, 0.85f, 0.83f};
    c.settings.ambientIrradiance = {0.01f, 0.011f, 0.012f};
    c.settings.response.kind = proto::ResponseKind::kCurve;
    c.settings.response.curve = {
        {{0.0f, 0.2f, 0.5f, 1.0f}, {0.0f, 0.21f, 0.52f, 1.0f}, {0.01f, 0.19f, 0.49f, 0.98f}}};
    c.settings.peakIrradiance = 2.5f;
    c.settings.gain = 1.25f;

    c.model.harmonics = 2;  // C = 18 values per texel: 5 layers, the last half padding
    c.model.lambda = 0.5;
    // A θs basis of two functions, √(2/π)·cos θs and √(2/π)·cos 2θs: orthonormal over [0, π].
    const auto unit = static_cast<float>(std::sqrt(2.0 / 3.14159265358979323846));
    c.model.thetaBasis = {0, unit, 0, 0, 0, 0, 0, 0, unit, 0};
    c.textureWidth = 5;
    c.textureHeight = 3;
    c.textureWrapsU = true;
    const std::size_t texels = 15;
    const std::size_t values = 18;

    bake::BundleRegion base;
    base.name = "base";
    base.coefficients.encoding = proto::CoefficientEncoding::kFull;
    base.coefficients.coefficients.resize(texels * values);
    for (std::size_t i = 0; i < base.coefficients.coefficients.size(); ++i) {
        base.coefficients.coefficients[i] = 0.01f * static_cast<float>(i % 97) - 0.3f;
    }
    bake::BundleRegion glaze;
    glaze.name = "glaze";
    glaze.coefficients.encoding = proto::CoefficientEncoding::kLowRank;
    glaze.coefficients.rank = 5;  // 2 layers, 3 padding values
    glaze.coefficients.mean.resize(values);
    glaze.coefficients.basis.resize(5 * values);
    glaze.coefficients.weights.resize(texels * 5);
    for (std::size_t i = 0; i < values; ++i) {
        glaze.coefficients.mean[i] = 0.02f * static_cast<float>(i);
    }
    for (std::size_t i = 0; i < glaze.coefficients.basis.size(); ++i) {
        glaze.coefficients.basis[i] = std::sin(0.37f * static_cast<float>(i));
    }
    for (std::size_t i = 0; i < glaze.coefficients.weights.size(); ++i) {
        glaze.coefficients.weights[i] = 3.0f * std::cos(0.11f * static_cast<float>(i));
    }
    c.composed = base.coefficients;
    c.regions = {base, glaze};

    bake::WeightPreset stripes;
    stripes.name = "stripes";
    stripes.encoding = proto::AlphaEncoding::kUnorm8;
    bake::WeightPreset fade;
    fade.name = "fade";
    fade.encoding = proto::AlphaEncoding::kFloat16;
    for (bake::WeightPreset* preset : {&stripes, &fade}) {
        preset->alpha.resize(2 * texels);
        for (std::size_t t = 0; t < texels; ++t) {
            const float alpha = preset == &stripes ? static_cast<float>(t % 4) / 7.0f
                                                   : static_cast<float>(t) / 14.0f;
            preset->alpha[t] = alpha;
            preset->alpha[texels + t] = 1.0f - alpha;
        }
    }
    c.presets = {stripes, fade};
    return c;
}

}  // namespace vpe::testing
