// SPDX-License-Identifier: MIT
// The measured light (vpe radiometry) as the bundle carries it (format 1.4): the maps on the
// projector's pixels, completed where the bundle's mesh is lit but the camera did not see it.
#pragma once

#include <cstddef>

#include "vpe/bake/bundle_writer.h"
#include "vpe/radiometry/projector_radiometry.h"

namespace vpe::bake {

struct MeasuredLightBake {
    BundleRadiometry radiometry;
    std::size_t covered = 0;    // projector pixels whose ray meets the mesh
    std::size_t measured = 0;   // of them, with a measurement
    std::size_t completed = 0;  // of them, completed from their neighbours
};

// Per projector pixel the mesh covers: the measurement where there is one; elsewhere F from the
// nearest measured pixels' albedo (F divided by the geometry's cos θ / d², grown outwards ring
// by ring) times this pixel's own geometry, and D grown the same way — the camera's blind spots
// (behind a handle, under the rim) lit as their neighbours are. Uncovered pixels are 0: the
// renderer shows nothing there. Throws InputError when the maps are not the projector's size.
MeasuredLightBake bakeMeasuredLight(const radiometry::ProjectorRadiometry& measured,
                                    const BundleMesh& mesh,
                                    const proto::ProjectorCalibration& projector,
                                    const std::filesystem::path& source);

}  // namespace vpe::bake
