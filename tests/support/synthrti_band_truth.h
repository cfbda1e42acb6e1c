// SPDX-License-Identifier: MIT
// Ground-truth material labels for SynthRTI's Multi sets, which ship none. Their materials are
// laid out on a grid of bands — columns vary the BRDF parameters, rows the base colour — so
// the truth is derived from that geometry: the grid's lines are located in the images, then
// the lines along which nothing changes are dropped (the two bands are one material). See
// docs/segmentation.md for the measurements behind each choice.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace vpe::testing {

struct BandGridOptions {
    // The finest grid every Multi layout is made of: 8 vertical bands (40 px at 320 px) and 16
    // horizontal ones (20 px); coarser layouts are unions of these bands.
    int columns = 8;
    int rows = 16;
    // Lines are located piece by piece, this long, to follow the texture where the surface's
    // relief bends it (Object2).
    int pieceLength = 20;
    int pieceSearch = 4;  // pixels either side of the line's overall position
    // How far the bands' rendered size may differ from the nominal (image size / bands): on
    // Object2 some layouts are magnified by 15%.
    double minScale = 0.8;
    double maxScale = 1.25;
};

// A line of the grid: where it lies overall and in each piece along it. Position p means the
// line runs between pixels ⌈p⌉ − 1 and ⌈p⌉ (pixel centres p − ½ and p + ½).
struct BandLine {
    double position = 0;
    std::vector<double> pieces;
};

struct BandGrid {
    int width = 0;
    int height = 0;
    int pieceLength = 20;
    std::vector<BandLine> columnLines;  // vertical lines, columns − 1
    std::vector<BandLine> rowLines;     // horizontal lines, rows − 1
    int columnOf(int x, int y) const;
    int rowOf(int x, int y) const;
};

// Locates the grid's lines from the edges in all the captures' images summed: the lines are
// taken evenly spaced first (offset and spacing fitted to the edge profile), then each moves
// to the nearest peak of the profile, then each piece of it to the nearest local peak.
BandGrid locateBandGrid(const std::vector<std::filesystem::path>& captures,
                        const BandGridOptions& options);

struct BandMergeOptions {
    // A line separates two materials when some image and channel differs across it by at
    // least this much in most of the line's pieces (8-bit sRGB levels).
    double boundaryLevels = 8.0;
    // Pixels compared on each side of a line are this far from it: clear of the one-pixel
    // anti-aliasing and of the piece's position error.
    int edgeOffset = 3;
};

struct LineContrasts {
    std::vector<double> columnLines;  // 8-bit sRGB levels
    std::vector<double> rowLines;
};

// Measures how much the capture changes across each line of the grid.
LineContrasts measureLineContrasts(const std::filesystem::path& capture, const BandGrid& grid,
                                   const BandMergeOptions& options);

struct BandTruth {
    int materialColumns = 0;  // bands after merging
    int materialRows = 0;
    int materials = 0;                 // materialColumns × materialRows
    std::vector<std::uint8_t> labels;  // [y][x], row-major over the merged bands
};

// Drops the lines below the threshold and paints a label per remaining grid cell.
BandTruth labelBands(const BandGrid& grid, const LineContrasts& contrasts, double boundaryLevels);

}  // namespace vpe::testing
