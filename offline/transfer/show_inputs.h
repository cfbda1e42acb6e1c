// SPDX-License-Identifier: MIT
// ShowInputs: a show's bundles and the synthetic truth they are checked against, opened and
// checked to fit together, and where visitors stand around the object (show_fidelity.h and
// visitors_together.h both check a show).
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/transfer/synthetic_truth.h"

namespace vpe::transfer::detail {

class ShowInputs {
public:
    // Throws InputError naming the file that is missing or does not fit: 1 to 32 bundles of one
    // object, textures the truth's size.
    ShowInputs(const std::filesystem::path& capture,
               const std::vector<std::filesystem::path>& bundles);

    const SyntheticTruth& truth() const { return truth_; }
    const std::vector<std::unique_ptr<renderer::BundleScene>>& scenes() const { return scenes_; }
    // The object's middle, and how far visitors stand from it: 4 times its height.
    const renderer::Vec3d& centre() const { return centre_; }
    double distance() const { return distance_; }
    // An eye (or a lamp) at `distance` from the middle, at an azimuth (0 = +z, the front; 90° =
    // +x) and elevation in degrees.
    renderer::Vec3d at(double azimuthDegrees, double elevationDegrees) const;

private:
    SyntheticTruth truth_;
    std::vector<proto::BundleFile> files_;
    std::vector<std::unique_ptr<renderer::BundleScene>> scenes_;
    renderer::Vec3d centre_;
    double distance_ = 0;
};

// The frame a projector is sent: 8-bit levels, as the device's framebuffer holds them.
renderer::RgbImage quantized(renderer::RgbImage levels);

}  // namespace vpe::transfer::detail
