// SPDX-License-Identifier: MIT
// The conversions from the offline world to the bundle's: a model file's coefficients into
// the bundle's texel order, scene/'s mesh, calibration and response into proto's types.
// Conventions that differ, and are converted here (once): mesh UVs follow OBJ (v = 0 at the
// bottom of the texture), bundle UVs have (0, 0) at the top-left texel; a sampled response
// curve may have any levels, the bundle's is sampled evenly.
#pragma once

#include <filesystem>
#include <vector>

#include "vpe/bake/bundle_writer.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/response_input.h"
#include "vpe/scene/screen_mesh.h"

namespace vpe::bake {

struct CoefficientTexture {
    int width = 0;
    int height = 0;
    int harmonics = 0;
    double lambda = 0;
    bool tilesU = false;        // the model file says it tiles in u (vpe quilt on a wrapping mesh)
    std::vector<float> values;  // C per texel, proto::bundleCoefficientIndex order
    std::vector<unsigned char> valid;  // per texel
    // The relief, when the model carries one: the detail normal's x and y per texel
    // (proto/detail_normal.h), (0, 0) where invalid; empty when it has none.
    std::vector<float> detailNormals;
};

// Reads a model file (vpe fit, quilt, compose): the coefficients and the relief. Invalid
// texels are zero (and flat).
CoefficientTexture readCoefficientTexture(const std::filesystem::path& model);

BundleMesh toBundleMesh(const scene::ScreenMesh& mesh);
proto::ProjectorCalibration toBundleProjector(const scene::ProjectorCalibration& projector);
// Sampled curves are resampled at `samples` even levels (linear in between, as both sides
// interpolate); gammas stay gammas.
proto::ResponseCurves toBundleResponse(const scene::ResponseInput& response, int samples = 256);

}  // namespace vpe::bake
