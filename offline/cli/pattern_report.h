// SPDX-License-Identifier: MIT
// What the `strokes` and `quilted` entries of a weight spec decided and the streaks their
// normalized weights show, for `vpe compose` and `vpe weights`: one line per entry on stderr
// and JSON.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/texture/weight_maps.h"

namespace vpe::cli {

// Sets json["strokes"] and json["quilted"]: one element per such entry that is not inverted
// (an inverted one repeats its pattern) with "region", "composed" (the streaks where the
// entry's normalized α ≥ ½) and "source" (the label map's region, when there is one); strokes
// add their parameters, the body width and spread as fitted.
void reportPatterns(const std::vector<texture::WeightSource>& sources,
                    const texture::WeightMaps& weights, nlohmann::json& json);

}  // namespace vpe::cli
