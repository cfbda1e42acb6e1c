// SPDX-License-Identifier: MIT
// writeRelightWeb: encodes a relightable picture (anything that renders the subject from the
// capture's view under a directional light) as a Relight web RTI — info.json plus
// plane_N.jpg, bilinear light grid, mrgb PCA planes — that OpenLIME shows in a browser.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "vpe/capture/capture.h"

namespace vpe::relight_web {

// Fills `rgb` (width·height·3, interleaved, row 0 at the top) with the subject as seen under
// a directional light towards `towardsLight` (unit): sRGB-encoded values in [0, 1], the
// units of the photographs the format was made for.
using LightRenderer =
    std::function<void(const proto::Vec3d& towardsLight, std::vector<float>& rgb)>;

// What the grid's nodes hold.
enum class GridValues {
    kNodes,         // the subject under each node's light (exact at the nodes)
    kLeastSquares,  // the values whose interpolation best matches a twice-as-fine grid
};

struct RelightWebOptions {
    int resolution = 8;  // light grid side (Relight's default)
    int planes = 9;      // PCA planes; a multiple of 3, as OpenLIME's mrgb shader reads 3 a JPEG
    int quality = 95;    // JPEG quality of the planes (Relight's default)
    GridValues grid = GridValues::kLeastSquares;
    unsigned threads = 1;
};

struct RelightWebSummary {
    int width = 0;
    int height = 0;
    int planes = 0;
    int resolution = 0;
    double retainedVariance = 0;  // fraction of the grid images' variance the planes keep
    std::uintmax_t bytes = 0;     // size on disk of info.json and the planes
    // Keeping the decoded light field non-negative (OpenLIME takes pow() of it): pixels whose
    // least-squares coefficients dipped below the floor at some grid node and were solved
    // under it; pixels solved again because the planes' rounding and JPEG took a node below
    // it, and the rounds of that; the largest lift of the mean at a node that the rounds
    // left short (0 when they sufficed); the lowest value decoded at any node (> 0).
    std::size_t flooredPixels = 0;
    std::size_t repairedPixels = 0;
    int repairRounds = 0;
    double meanLift = 0;
    double lowestAtNodes = 0;
    double blackLevel = 0;  // the lowest value the grid was encoded with (black's level)
};

// Writes the export into `folder` (replaced as a whole, atomically). `captureLights` go to
// info.json's "lights", as Relight records the lights it was built from. Throws InputError
// for options out of range.
RelightWebSummary writeRelightWeb(const std::filesystem::path& folder, int width, int height,
                                  const LightRenderer& render, const RelightWebOptions& options,
                                  const std::vector<proto::Vec3d>& captureLights = {});

}  // namespace vpe::relight_web
