// SPDX-License-Identifier: MIT
// A bundle's coefficient maps re-expressed in its θs basis (proto/theta_basis.h), and the
// evaluation a renderer does with them: what the GLES renderer uploads and computes, written
// once in C++ so that the GPU's frames can be compared step by step (and the loss of the
// reduced basis measured against the exact model).
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/proto/theta_basis.h"

namespace vpe::renderer {

// Per texel of the region's map, thetaMaterialSize(K) values (proto::projectToThetaBasis of
// the texel's coefficients), texel-major, rows from the top as in the bundle. Low-rank maps are
// projected in their own space (the mean and the R basis vectors, then Σ w_r per texel: the
// projection is linear), full maps texel by texel.
std::vector<float> thetaMaterialMap(const proto::CoefficientMapView& map,
                                    const proto::ThetaBasis& basis);

// The model's f per channel for a material (thetaMaterialSize(table.size) values):
//   kd·max(cos θd, 0) + Σ_j u_j·h_j(θs),  h_j from the table at proto::thetaTableParameter.
template <typename Material>
std::array<double, 3> evaluateThetaMaterial(const Material* material,
                                            const proto::ThetaTable& table, double cosThetaD,
                                            double cosThetaS) {
    const double x = proto::thetaTableParameter(std::clamp(cosThetaS, -1.0, 1.0));
    const double lambert = std::max(cosThetaD, 0.0);
    std::array<double, 3> f{};
    for (int c = 0; c < 3; ++c) {
        double value = static_cast<double>(material[c]) * lambert;
        for (int j = 0; j < table.size; ++j) {
            value += static_cast<double>(material[3 * (1 + j) + c]) * table.sample(j, x);
        }
        f[static_cast<std::size_t>(c)] = value;
    }
    return f;
}

}  // namespace vpe::renderer
