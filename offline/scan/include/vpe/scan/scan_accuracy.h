// SPDX-License-Identifier: MIT
// ScanAccuracy: a scan against the simulator's truth (vpe synth-procam's truth/ folder) — how
// much of the object it measured, how well, and how many camera pixels it decoded wrong.
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>

#include "vpe/scan/projector_surface.h"

namespace vpe::scan {

struct ScanAccuracy {
    // Projector pixels whose lit object point the camera sees, and how many of them were
    // measured: the coverage.
    std::size_t seen = 0, measuredSeen = 0;
    double coverage = 0;
    // Distance between measured and true points, over measured pixels that light the object
    // (millimetres), and the angle between normals (degrees).
    double depthRmsMm = 0, depthP99Mm = 0, normalMedianDeg = 0, normalP95Deg = 0;
    // Measured pixels where the truth has no surface (false measurements).
    std::size_t measuredWithoutTruth = 0;
    // Camera pixels: decoded, decoded more than one projector pixel from the coordinate the
    // pixel sees (the light-weighted mean over its area: CameraTruth), and their share; decoded
    // where the pixel sees no lit point. wrongDecodes counts the pixels placed to better than a
    // projector pixel (precision ≤ 1 px: the surface's points); those its Gray bin alone placed
    // are coarse by design, counted apart (coarseDecodes) and judged by wrongCodes.
    std::size_t decoded = 0, wrongDecodes = 0, decodedWithoutTruth = 0, coarseDecodes = 0;
    double wrongDecodeShare = 0, coarseShare = 0;
    std::size_t wrongAmongAll = 0;  // more than a pixel off, the coarse ones too
    double wrongAmongAllShare = 0;
    double decodeRmsPx = 0;  // over decoded pixels with a truth, both axes
    // Camera pixels that see a point the projector lights (the truth has a coordinate there: lit
    // and unshadowed), how many of them were decoded, and the share.
    std::size_t litSeen = 0, decodedLitSeen = 0;
    double litDecodedShare = 0;
    // Decoded pixels whose error exceeds their own claim by more than one projector pixel: the
    // claim is ±√3·σ of DecodedScan::precision, a whole Gray bin's half width for a pixel its
    // bin placed. A wrong code, where wrongDecodes also counts a right but imprecise one.
    std::size_t wrongCodes = 0;
    double wrongCodeShare = 0;
    // The decoded pixels with a truth by what placed them (PositionSource), and their RMS error.
    std::array<std::size_t, structured_light::kPositionSourceCount> bySource{};
    std::array<double, structured_light::kPositionSourceCount> rmsBySourcePx{};
    // The same against the coordinate of the pixel's centre ray alone: stricter where one camera
    // pixel sees many projector pixels (grazing surfaces), whose mean is not the centre's.
    std::size_t wrongAtCentre = 0;
    double wrongAtCentreShare = 0;
};

// Reads truth/camera-truth.exr and truth/projector-truth.exr (InputError naming a missing or
// mismatched file).
ScanAccuracy compareWithTruth(const structured_light::DecodedScan& decoded,
                              const ProjectorSurface& surface,
                              const std::filesystem::path& truthFolder);

}  // namespace vpe::scan
