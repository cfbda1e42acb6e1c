// SPDX-License-Identifier: MIT
// Visitors together (`vpe show-check --together`): a gallery's case, not a lone tracked visitor's.
// One virtual light; each projector's frame drawn once, for the show's viewer model; several
// visitors standing around the object at once, each scored against the truth from where they
// stand (docs/visitors.md).
#pragma once

#include <string>
#include <vector>

#include "vpe/transfer/show_fidelity.h"

namespace vpe::transfer {

// Whom the frames are drawn for.
enum class ViewerModel {
    kBundle,         // the one eye each bundle carries (viewer_position): today's device
    kProjectorSide,  // per projector, an eye at the visitors' height on that projector's side
    kZone,           // per surface point, the mean of what every visitor who sees it should see
    kTracked,        // each visitor alone, the frames redrawn for their eyes: the upper bound
};

// "bundle", "projector-side", "zone", "tracked"; parseViewerModel throws InputError naming
// `what` for another word.
std::string viewerModelName(ViewerModel model);
ViewerModel parseViewerModel(const std::string& word, const std::string& what);

struct TogetherOptions {
    ShowCheckOptions show;  // capture, bundles, view size and fov, threads, out
    int eyeVisitors = 8;    // around the object at show.elevationDegrees
    int childVisitors = 2;  // at childElevationDegrees, between eye visitors
    double childElevationDegrees = -20;
    bool visitorAbove = true;  // one looking down from aboveElevationDegrees
    double aboveElevationDegrees = 70;
    // The one light, from the front (azimuth 0): show.lightAzimuthDegrees and
    // show.lightElevationDegrees.
    // A true highlight counts as seen where the show has one within this visual angle.
    double highlightDegrees = 2;
    double highlightShare = 0.02;  // the top share of a view's view-dependent light
};

struct VisitorCheck {
    std::string where;  // "eye", "child", "above"
    double azimuthDegrees = 0, elevationDegrees = 0;
    // Transfer PSNR (dB; 8-bit sRGB at one exposure for the room, the brightest view's) over
    // every pixel of the object some projector reaches, dark ones included.
    double psnr = 0;
    // Of the view's true highlights (its top highlightShare of the view-dependent light, by
    // luminance), the share the show has a highlight within highlightDegrees of.
    double highlightShare = 0;
    std::size_t seenPixels = 0, litPixels = 0;
};

struct TogetherReport {
    ViewerModel model = ViewerModel::kBundle;
    std::vector<VisitorCheck> visitors;
    // Over the visitors at eye and child height; the one above is reported apart.
    double worstPsnr = 0, meanPsnr = 0, meanHighlightShare = 0, worstHighlightShare = 0;
    double seconds = 0;
};

// Throws InputError when an input is missing or they do not fit together.
TogetherReport checkVisitorsTogether(const TogetherOptions& options, ViewerModel model);

}  // namespace vpe::transfer
