// SPDX-License-Identifier: MIT
// Filling the kernel's per-chunk inputs (geometry of kLanes pixels, light list, pointers into
// a SampleBand) from a capture: shared by fitting and the sweep.
#pragma once

#include <vector>

#include "vpe/capture/capture.h"
#include "vpe/capture/sample_band.h"
#include "vpe/capture/surface_geometry.h"
#include "vpe/fit/normal_equations.h"
#include "vpe/normals/normal_map.h"

namespace vpe::fit {

std::vector<KernelLight> kernelLights(const capture::Capture& capture);

KernelLightSet kernelLightSet(const capture::Capture& capture,
                              const std::vector<KernelLight>& lights);

// Geometry of pixels x0 .. x0 + kLanes − 1 of image row y; lanes past the row end or without
// a normal get a harmless placeholder and laneValid = false.
void fillChunkGeometry(const capture::SurfaceGeometry& geometry, const normals::NormalMap& normals,
                       int x0, int y, ChunkGeometry& chunk, bool (&laneValid)[kLanes]);

// One lane of a chunk: pixel (x, y), or a placeholder when x < 0.
void fillChunkLane(const capture::SurfaceGeometry& geometry, const normals::NormalMap& normals,
                   int x, int y, int lane, ChunkGeometry& chunk, bool& laneValid);

ChunkObservations chunkObservations(const capture::SampleBand& band, int row, int x0);

}  // namespace vpe::fit
