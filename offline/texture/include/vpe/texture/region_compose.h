// SPDX-License-Identifier: MIT
// Composition of quilted region maps into one texture (paper eq. 20): I = Σ_k α_k I_k with
// Σ_k α_k = 1. The Fourier BRDF is linear in its coefficients, so blending the coefficients
// with α gives exactly the blend of the regions' renderings under any light, normal and view;
// the composite is one model file and renders at the cost of one region.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include "vpe/model/fourier_model_file.h"
#include "vpe/texture/weight_maps.h"

namespace vpe::texture {

// Opens every region map and checks they agree on size and harmonics; returns the first
// one's header. Throws InputError naming the map that differs and how.
model::ModelInfo checkRegionMaps(const std::vector<std::filesystem::path>& regionMaps);

struct ComposeReport {
    int width = 0;
    int height = 0;
    int harmonics = 0;
    int regions = 0;
    std::vector<double> meanWeight;  // per region, over the output
    // Pixels where a region with α > 0 had no valid coefficients: written invalid (zeros),
    // since a blend with a hole is not the material.
    std::size_t invalidPixels = 0;
};

// Writes the composite to `out` (a model file: paper variant, normals (0, 0, 1), rms the
// α-weighted sum of the regions' rms — by the triangle inequality an upper bound of the
// blend's residual). `weights` must be normalized and of the maps' size. Channels are
// `storage`, or unset: as the first region map's.
ComposeReport composeRegionMaps(const std::vector<std::filesystem::path>& regionMaps,
                                const WeightMaps& weights, const std::filesystem::path& out,
                                std::optional<model::ModelStorage> storage = std::nullopt);

}  // namespace vpe::texture
