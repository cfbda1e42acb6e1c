// SPDX-License-Identifier: MIT
// Show fidelity (`vpe show-check`): what visitors walking around the object see of a show of
// several projectors (vpe bake with several), against the true material of a `vpe synth`
// capture: the projected light's transfer PSNR, the step where one projector hands over to
// another, and how much of what they see some projector lights (docs/multi-projector.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vpe::transfer {

struct ShowCheckOptions {
    std::filesystem::path capture;               // what `vpe synth --out` wrote
    std::vector<std::filesystem::path> bundles;  // the show's, one per projector
    int views = 8;                               // around the object, evenly in azimuth
    double elevationDegrees = 10;                // the visitors' eyes above the object's middle
    // The light follows each visitor: this far to their left and this high (the transfer
    // check's key light), so that every view is lit alike.
    double lightAzimuthDegrees = -35, lightElevationDegrees = 30;
    int viewWidth = 480, viewHeight = 360;
    double fovDegrees = 20;
    std::filesystem::path out;  // per view: truth and show pictures, and where each is lit
    int threads = 0;
};

struct ShowViewCheck {
    double azimuthDegrees = 0;
    // Transfer PSNR (dB; 8-bit sRGB at the truth's exposure, as vpe transfer) over the seen
    // pixels some projector lights.
    double psnr = 0;
    // The mean step between neighbouring pixels where the set of projectors reaching them
    // changes (a blend boundary), over the mean step of the other neighbour pairs within 4
    // pixels of it (docs/seams.md's across / beside), measured on the light the visitor sees
    // relative to the material rendered directly (the texture and shading cancel; a seam in the
    // light does not).
    double seamStepRatio = 0;
    // The same measure on the pictures themselves, texture and all: the show's, and the
    // truth's, which has no seam (what the measure gives on a seamless surface there).
    double pictureSeamStepRatio = 0, truthSeamStepRatio = 0;
    std::size_t boundaryPairs = 0;
    std::size_t seenPixels = 0, litPixels = 0;  // on the object; of them lit by a projector
};

struct ShowCheckReport {
    std::vector<ShowViewCheck> views;
    double meanPsnr = 0, worstPsnr = 0;
    double worstSeamStepRatio = 0;  // over views with boundary pairs
    double litShare = 0;            // of the seen pixels of every view, lit
    double seconds = 0;
};

// Throws InputError when an input is missing or they do not fit together.
ShowCheckReport checkShow(const ShowCheckOptions& options);

}  // namespace vpe::transfer
