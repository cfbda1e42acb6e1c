// SPDX-License-Identifier: MIT
// Chooses where a capture's normals come from: an explicit file, the capture's own normal
// map (manifest or normals.png beside the .lp), or photometric stereo on the images.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "vpe/capture/capture.h"
#include "vpe/normals/normal_map.h"

namespace vpe::normals {

struct NormalsResult {
    NormalMap normals;
    std::string source;      // for reports: the file, or "photometric stereo"
    bool estimated = false;  // photometric stereo, not a given map
};

NormalsResult acquireNormals(const capture::Capture& capture,
                             const std::optional<std::filesystem::path>& overridePath, int width,
                             int height, unsigned threads);

}  // namespace vpe::normals
