// SPDX-License-Identifier: MIT
// ViewerEyes: whom the load-time passes draw the view-dependent light for — one viewer, or the
// bundle's viewing zone (proto/viewing_zone.h) with the viewer where no eye of the zone sees a
// point — and the uniforms that carry them to vpeZoneViewer (shading_glsl.h).
#pragma once

#include <array>
#include <vector>

namespace vpe::renderer::gles {

struct ViewerEyes {
    std::array<float, 3> viewer{};
    std::vector<std::array<float, 3>> zone;  // at most proto::kMaxViewingZone; empty: none

    // Sets uViewer, uZone and uZoneCount of the program in use.
    void setUniforms(unsigned program) const;
};

}  // namespace vpe::renderer::gles
