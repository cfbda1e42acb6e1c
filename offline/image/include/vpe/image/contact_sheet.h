// SPDX-License-Identifier: MIT
// Contact sheets: labelled pictures in a grid, one PNG, for the commands whose results a person
// would rather look at than read (vpe scan, vpe calibrate).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace vpe::image {

// A picture to show: display values in [0, 1] (already encoded for the eye), 1 or 3 channels.
struct SheetTile {
    std::string label;
    int width = 0, height = 0, channels = 3;
    std::vector<float> pixels;
};

// Each tile scaled to `tileWidth` pixels wide, its label in the top-left corner, `columns` to a
// row, 4 pixels apart on black; written atomically as PNG. Throws InputError naming `path`.
void writeContactSheet(const std::filesystem::path& path, const std::vector<SheetTile>& tiles,
                       int columns, int tileWidth = 360);

// A false-colour tile of a scalar map: values mapped from [low, high] through a perceptual ramp
// (dark blue → yellow), NaN drawn black.
SheetTile scalarTile(std::string label, int width, int height, const std::vector<float>& values,
                     float low, float high);

}  // namespace vpe::image
