// SPDX-License-Identifier: MIT
// Pieces of the synthetic bundles the bundle-load and GLES frame benchmarks write: a flat
// grid mesh, the 1080p projector facing it, the paper's model in two low-rank regions, and a
// two-region stripes preset.
#pragma once

#include "vpe/bake/bundle_writer.h"

namespace vpe::benchmarks {

// A flat `width` × `height` rectangle (metres, centred on the origin, in z = 0), `cells` quads
// a side; y = height·(v − ½), so a negative height puts v = 0 at the top. Normals (0, 0, normalZ).
bake::BundleMesh planeMesh(int cells, float width, float height, float normalZ);

// 1920 × 1080, f = 2000 px, looking down the z axis from 1.5 m.
proto::ProjectorCalibration benchmarkProjector();

// The paper's model (M = 10, λ = 3.14) on a size × size texture.
void usePaperModel(bake::BundleContents& contents, int size);

// Region `index` of the benchmarks' two ("clay", "glaze"), low-rank of `rank`; its mean, basis
// and weights are the caller's to fill.
bake::BundleRegion lowRankRegion(int index, int rank);

// Two regions' weights: horizontal stripes and their complement, size × size texels.
bake::WeightPreset stripesPreset(int size);

}  // namespace vpe::benchmarks
