// SPDX-License-Identifier: MIT
#include "show_inputs.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vpe/common/input_error.h"
#include "vpe/transfer/transfer_fidelity.h"

namespace vpe::transfer::detail {

ShowInputs::ShowInputs(const std::filesystem::path& capture,
                       const std::vector<std::filesystem::path>& bundles)
    : truth_(capture) {
    if (bundles.empty() || bundles.size() > 32) {
        throw common::InputError("show check: give 1 to 32 bundles, one per projector");
    }
    for (const std::filesystem::path& path : bundles) {
        files_.push_back(proto::BundleFile::open(path));  // a BundleError is bad input
        const proto::BundleView& bundle = files_.back().view();
        if (bundle.textureWidth() != truth_.width() || bundle.textureHeight() != truth_.height()) {
            throw common::InputError(
                path, "textures of " + std::to_string(bundle.textureWidth()) + " x " +
                          std::to_string(bundle.textureHeight()) + ", the capture's truth is " +
                          std::to_string(truth_.width()) + " x " + std::to_string(truth_.height()));
        }
        if (bundle.mesh().positions.size() != files_.front().view().mesh().positions.size()) {
            throw common::InputError(path, "not the same object as the first bundle's");
        }
    }
    for (const proto::BundleFile& file : files_) {
        scenes_.push_back(std::make_unique<renderer::BundleScene>(file.view(), ""));
    }
    const auto& positions = files_.front().view().mesh().positions;
    const MeshBounds bounds = meshBounds({positions.begin(), positions.end()});
    centre_ = bounds.centre();
    distance_ = 4.0 * (bounds.upper.y - bounds.lower.y);
}

renderer::Vec3d ShowInputs::at(double azimuthDegrees, double elevationDegrees) const {
    const renderer::Vec3d d = directionAt(azimuthDegrees, elevationDegrees);
    return {centre_.x + distance_ * d.x, centre_.y + distance_ * d.y, centre_.z + distance_ * d.z};
}

renderer::RgbImage quantized(renderer::RgbImage levels) {
    for (float& v : levels.values) {
        v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
    }
    return levels;
}

}  // namespace vpe::transfer::detail
