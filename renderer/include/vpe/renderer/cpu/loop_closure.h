// SPDX-License-Identifier: MIT
// Closing the loop: how far what a visitor would see (the white object lit by the projector
// frame, simulateVisitorView) is from the material rendered directly on the object
// (renderDirectView), over the viewer pixels where the comparison is meaningful — seen, lit
// by the projector, and blending only projector pixels that cover the object unclipped.
#pragma once

#include <cstddef>

#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"

namespace vpe::renderer {

struct LoopClosure {
    std::size_t seenPixels = 0;      // viewer pixels on the object
    std::size_t comparedPixels = 0;  // of those, lit and clear of clipping and silhouettes
    std::size_t shadowedPixels = 0;  // on the object, out of the projector's reach
    // Relative error |simulated − direct| / direct per channel, over compared pixels and
    // channels whose direct radiance is at least 5% of the brightest (below that, relative
    // errors measure nothing anyone sees).
    double meanRelativeError = 0;
    double p99RelativeError = 0;
    double maxRelativeError = 0;
    // 10·log10(peak² / MSE) over the compared pixels, peak the brightest direct radiance.
    double psnr = 0;
};

LoopClosure compareVisitorViews(const ProjectorFrame& frame, const SimulatedView& simulated,
                                const DirectView& direct);

}  // namespace vpe::renderer
