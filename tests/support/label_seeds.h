// SPDX-License-Identifier: MIT
// Seed points from a reference labelling, standing in for the user of the paper's seeded
// segmentation: one pixel per label, the one deepest inside its region, as a person picking a
// seed on a material would (never on an edge, where the average colour is mixed).
#pragma once

#include <string>
#include <vector>

#include "vpe/segment/label_map.h"

namespace vpe::testing {

// For each label present (ascending), the pixel farthest (city-block distance) from any other
// label and from the picture's border; ties: the first in row order.
std::vector<segment::PixelSeed> innermostPixels(const segment::LabelMap& map);

// "x,y;x,y;...", the form `vpe segment --seeds` takes.
std::string seedsArgument(const std::vector<segment::PixelSeed>& seeds);

}  // namespace vpe::testing
