// SPDX-License-Identifier: MIT
// quiltTexture: `vpe quilt`. Reads a model and its region labels, quilts a texture of the
// requested size for every region, and writes DIR/region<k>.exr (a vpe model file of the
// synthesized coefficients, normals +z, variant "paper": a texture holds materials, never a
// capture's light transport) and DIR/positions<k>.exr (where every output pixel was copied
// from; the folder's format is texture/quilt_folder.h), plus DIR/quilt.json. Label 255 marks
// pixels that belong to no region; pixels without a valid fit are never copied. DIR appears
// complete or not at all.
#pragma once

#include <filesystem>
#include <vector>

#include "quilt/image_quilter.h"

namespace vpe::quilt {

struct QuiltTextureOptions {
    std::filesystem::path model;
    std::filesystem::path labels;
    std::filesystem::path out;
    int width = 512;
    int height = 512;
    QuiltSettings settings;
};

struct RegionReport {
    int region = 0;
    std::size_t sourcePixels = 0;
    RegionQuilt quilt;  // positions dropped after writing; sizes and statistics kept
    double seconds = 0;
};

struct QuiltTextureReport {
    std::vector<RegionReport> regions;
    int channels = 0;
    double loadSeconds = 0;
    double quiltSeconds = 0;
    double writeSeconds = 0;
    double seconds = 0;
};

QuiltTextureReport quiltTexture(const QuiltTextureOptions& options);

}  // namespace vpe::quilt
