// SPDX-License-Identifier: MIT
// The conversions from the offline world to the bundle's: a model's coefficients into the
// bundle's texel order, scene/'s mesh, calibration and response into proto's types.
// Conventions that differ, and are converted here (once): mesh UVs follow OBJ (v = 0 at the
// bottom of the texture), bundle UVs have (0, 0) at the top-left texel; a sampled response
// curve may have any levels, the bundle's is sampled evenly.
#pragma once

#include <filesystem>
#include <vector>

#include "vpe/bake/bundle_writer.h"
#include "vpe/model/coefficient_image.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/response_input.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::bake {

// A model's coefficients in the bundle's order: C per texel, proto::bundleCoefficientIndex,
// zero where the texel is invalid.
std::vector<float> bundleCoefficients(const model::CoefficientImage& model);
// The model's relief as the bundle holds it: the detail normal's x and y per texel
// (proto/detail_normal.h), (0, 0) where invalid; empty when the model has none.
std::vector<float> bundleDetailNormals(const model::CoefficientImage& model);

BundleMesh toBundleMesh(const scene::ScreenMesh& mesh);
proto::ProjectorCalibration toBundleProjector(const scene::ProjectorCalibration& projector);
// Sampled curves are resampled at `samples` even levels (linear in between, as both sides
// interpolate); gammas stay gammas.
proto::ResponseCurves toBundleResponse(const scene::ResponseInput& response, int samples = 256);

}  // namespace vpe::bake
