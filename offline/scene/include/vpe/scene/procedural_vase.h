// SPDX-License-Identifier: MIT
// The built-in screen object of the demo: a small Bizen-like jar (tsubo) — narrow foot,
// full body with a high shoulder, short neck, slightly flared lip — as a surface of
// revolution about the y axis. Object frame: metres, y up, the centre of the foot at the
// origin; u = 0.5 faces +z (where the demo projector and viewer stand), so the texture seam
// u = 0 | 1 is at the back. Closed at the bottom, open at the top.
//
// Not the profile of `vpe synth`'s PotteryScene: that one is private to the renderer,
// unit-less (radius ≈ 1) and only a band of a body, with no foot, neck or lip; and the
// material travels to the screen object through its texture, so the two shapes need not
// agree.
#pragma once

#include "vpe/scene/screen_mesh.h"

namespace vpe::scene {

struct VaseParameters {
    double height = 0.15;  // metres, foot to lip
    int segments = 128;    // around the axis
    int rings = 96;        // along the side, foot to lip
    int baseRings = 8;     // across the bottom disc, centre to rim
};

// The jar's radius and its derivative d(radius)/dy at height y ∈ [0, height], metres.
double vaseRadius(double y, double height);
double vaseRadiusSlope(double y, double height);

// The jar as a mesh. Texture coordinates: u around the axis (i / segments, duplicated at the
// seam), v the arc length along the profile from the centre of the bottom to the lip, over
// its total length — texels are square along the profile wherever u is. Normals are the
// exact normals of the surface of revolution, outward; the rim of the foot is a hard edge
// (its ring appears twice, with the bottom's and the side's normal). Throws InputError for
// parameters out of range.
ScreenMesh makeProceduralVase(const VaseParameters& parameters = {});

}  // namespace vpe::scene
