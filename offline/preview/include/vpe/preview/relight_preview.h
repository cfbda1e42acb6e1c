// SPDX-License-Identifier: MIT
// RelightPreview: a model rendered under a few directional lights, side by side, seen from
// the front, for a quick look at what a fit learned. Tiles are subsampled to at most
// kMaxTile pixels on their longer side.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/model/fourier_model_file.h"

namespace vpe::preview {

class RelightPreview {
public:
    static constexpr int kMaxTile = 512;

    RelightPreview(int width, int height, int harmonics);
    // Rows may arrive in any order, from one thread at a time.
    void addRows(int rowBegin, const model::ModelRows& rows);
    void write(const std::filesystem::path& path) const;

    static const std::vector<proto::Vec3d>& lights();

private:
    int harmonics_, step_, tileWidth_, tileHeight_;
    std::vector<std::uint8_t> pixels_;
};

}  // namespace vpe::preview
