// SPDX-License-Identifier: MIT
// The seam u = 0 | 1 on a rendered frame: the radiance step between horizontally neighbouring
// projector pixels whose surface points lie on either side of it, against neighbours near it
// that do not cross it. For the seam test and the seam figure (scripts/seam-figure.sh).
#pragma once

#include <vector>

#include "vpe/proto/bundle.h"
#include "vpe/proto/vector_types.h"

namespace vpe::testing {

struct FrameSeamSteps {
    // Euclidean RGB differences of the target radiance (what the visitor sees, gain 1).
    std::vector<double> seam, interior;
    static double mean(const std::vector<double>& steps);
    static double quantile(std::vector<double> steps, double share);
    double ratio() const { return mean(seam) / mean(interior); }
};

// Renders the bundle's first preset with the CPU reference under a light at `light` (object
// frame, metres), seen from the bundle's viewer, and collects the steps of pixel pairs whose
// u both lie within `band` of the seam.
FrameSeamSteps measureFrameSeam(const proto::BundleView& bundle, const proto::Vec3d& light,
                                double band);

}  // namespace vpe::testing
