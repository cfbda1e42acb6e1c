// SPDX-License-Identifier: MIT
// The folder `vpe quilt` writes, as `vpe compose` and `vpe quilt-quality` read it:
// region<k>.exr (k = 0..K-1, one model file per region, all the same size and harmonics) and
// positions<k>.exr (where every pixel of region<k>.exr was copied from).
//
// A positions file holds float channels `source.x`, `source.y` and `region`: pixel (x, y) of
// region<r>.exr, r = the pixel's `region` value, is a copy of source pixel (source.x,
// source.y) of the model that was quilted (integers stored as floats). Readers dispatch on
// `region`, so one positions.exr covering several maps (one subimage each, or one region per
// pixel) reads the same. Source (-1, -1) means "no position" (a pixel that was not copied).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace vpe::quilt {

std::filesystem::path regionMapPath(const std::filesystem::path& dir, int region);
std::filesystem::path positionsPath(const std::filesystem::path& dir, int region);

// region0.exr, region1.exr, ... in region order. Throws InputError when the folder does
// not exist, holds no region0.exr, or skips an index (region2.exr without region1.exr).
std::vector<std::filesystem::path> listRegionMaps(const std::filesystem::path& dir);

// One region map's copy positions.
struct PositionMap {
    int width = 0;
    int height = 0;
    std::vector<std::int32_t> sourceX;  // per output pixel, row-major; -1: not known
    std::vector<std::int32_t> sourceY;

    void resize(int w, int h);
    std::size_t pixel(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
    bool known(std::size_t p) const { return sourceX[p] >= 0; }
};

// Writes one region map's positions (atomically), `region` in every pixel.
void writePositionMap(const std::filesystem::path& path, const PositionMap& map, int region);

// Reads positions<k>.exr for k = 0..regions-1, and positions.exr, whichever exist, into the
// map of the region each pixel names. Throws InputError naming the file (and pixel) when
// there is no positions file, a channel is missing, a size is not width × height, a value
// is not an integer, a region is not in [0, regions), a source position lies outside the
// sourceWidth × sourceHeight model, or two files or subimages give one pixel of one region.
std::vector<PositionMap> readPositionMaps(const std::filesystem::path& dir, int regions, int width,
                                          int height, int sourceWidth, int sourceHeight);

}  // namespace vpe::quilt
