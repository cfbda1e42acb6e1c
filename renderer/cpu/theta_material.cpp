// SPDX-License-Identifier: MIT
// thetaMaterialMap: a region's coefficients projected onto the θs basis.
#include "vpe/renderer/cpu/theta_material.h"

#include "vpe/proto/half_float.h"
#include "vpe/renderer/cpu/parallel_rows.h"

namespace vpe::renderer {

std::vector<float> thetaMaterialMap(const proto::CoefficientMapView& map,
                                    const proto::ThetaBasis& basis) {
    const proto::HalfLayers& layers = map.layers;
    const auto texels =
        static_cast<std::size_t>(layers.width) * static_cast<std::size_t>(layers.height);
    const auto values = static_cast<std::size_t>(proto::thetaMaterialSize(basis.size));
    const auto coefficients =
        static_cast<std::size_t>(3 * proto::coefficientCount(basis.harmonics));
    // Value i of texel t lives in layer i / 4, component i % 4 (proto/BUNDLE.md).
    const auto half = [&](std::size_t t, std::size_t i) {
        return proto::halfToFloat(layers.halves[((i / 4) * texels + t) * 4 + i % 4]);
    };
    std::vector<float> out(texels * values);
    if (map.encoding == proto::CoefficientEncoding::kFull) {
        forEachRow(layers.height, 0, [&](int y) {
            std::vector<float> texel(coefficients);
            for (int x = 0; x < layers.width; ++x) {
                const std::size_t t =
                    static_cast<std::size_t>(y) * static_cast<std::size_t>(layers.width) +
                    static_cast<std::size_t>(x);
                for (std::size_t i = 0; i < coefficients; ++i) {
                    texel[i] = half(t, i);
                }
                proto::projectToThetaBasis(basis, texel.data(), out.data() + t * values);
            }
        });
        return out;
    }
    // Low rank: material(t) = P(μ) + Σ_r w_r(t) P(B_r).
    const auto rank = static_cast<std::size_t>(map.rank);
    std::vector<double> projected((rank + 1) * values);
    proto::projectToThetaBasis(basis, map.mean.data(), projected.data());
    for (std::size_t r = 0; r < rank; ++r) {
        proto::projectToThetaBasis(basis, map.basis.data() + r * coefficients,
                                   projected.data() + (r + 1) * values);
    }
    forEachRow(layers.height, 0, [&](int y) {
        std::vector<double> weights(rank);
        for (int x = 0; x < layers.width; ++x) {
            const std::size_t t =
                static_cast<std::size_t>(y) * static_cast<std::size_t>(layers.width) +
                static_cast<std::size_t>(x);
            for (std::size_t r = 0; r < rank; ++r) {
                weights[r] = static_cast<double>(half(t, r));
            }
            for (std::size_t v = 0; v < values; ++v) {
                double value = projected[v];
                for (std::size_t r = 0; r < rank; ++r) {
                    value += weights[r] * projected[(r + 1) * values + v];
                }
                out[t * values + v] = static_cast<float>(value);
            }
        }
    });
    return out;
}

}  // namespace vpe::renderer
