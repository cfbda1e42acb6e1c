// SPDX-License-Identifier: MIT
// quiltTexture: `vpe quilt`. Reads a model and its region labels, quilts a texture of the
// requested size for every region, and writes DIR/region<k>.exr (a vpe model file of the
// synthesized coefficients, normals +z, variant "paper": a texture holds materials, never a
// capture's light transport) and DIR/positions<k>.exr (where every output pixel was copied
// from; the folder's format is quilt/quilt_folder.h), plus DIR/quilt.json. The size is
// given, or chosen for the screen object (the physical texel size of the capture kept); the
// texture tiles in u when the object's uv wraps, and quilt.json reports the texels' stretch
// on the object and the step across the u seam. Label 255 marks
// pixels that belong to no region; pixels without a valid fit are never copied. DIR appears
// complete or not at all.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/model/fourier_model_file.h"
#include "vpe/quilt/image_quilter.h"
#include "vpe/quilt/seam_statistics.h"
#include "vpe/scene/surface_scale.h"

namespace vpe::quilt {

// Whether the texture tiles in u: as the screen object's uv does (kAuto), or as told.
enum class WrapMode { kAuto, kOn, kOff };

// The largest side --size auto may choose: what a device bundle holds (GLES 3.1's guaranteed
// texture size on the Pi).
inline constexpr int kMaxAutoSide = 4096;

struct QuiltTextureOptions {
    std::filesystem::path model;
    std::filesystem::path labels;
    std::filesystem::path out;
    // The output size; unset: chosen from the screen object so that a texel is as long on it
    // as on the captured surface (scene::chooseTextureSize), at most kMaxAutoSide a side.
    std::optional<int> width, height;
    // The screen object the texture is for (empty: the built-in vase, as vpe bake's default).
    std::filesystem::path mesh;
    double meshMetresPerUnit = 1.0;
    // The capture's texel on its surface, millimetres; unset: the model's (from the capture's
    // manifest through vpe fit).
    std::optional<double> texelMm;
    WrapMode wrap = WrapMode::kAuto;
    QuiltSettings settings;
    // The region maps' channels; unset: as the source model's.
    std::optional<model::ModelStorage> storage;
};

struct RegionReport {
    int region = 0;
    std::size_t sourcePixels = 0;
    RegionQuilt quilt;  // positions dropped after writing; sizes and statistics kept
    // The step across u = 0 | 1 of the quilted coefficients against interior neighbours'
    // (column steps dropped after writing quilt.json; the summary kept).
    quilt::SeamStatistics seam;
    double seconds = 0;
};

struct QuiltTextureReport {
    std::vector<RegionReport> regions;
    int width = 0, height = 0;
    bool autoSize = false;
    bool wrapU = false;
    double texelMm = 0;  // the capture's (0: unknown)
    std::string mesh;    // what the texture was laid out for, for people
    bool meshWrapsU = false;
    scene::TexelStretch stretch;  // of the chosen size on that mesh
    int channels = 0;
    double loadSeconds = 0;
    double quiltSeconds = 0;
    double writeSeconds = 0;
    double seconds = 0;
};

QuiltTextureReport quiltTexture(const QuiltTextureOptions& options);

// The layout (size, texel, wrapping, mesh, stretch) and each region's seam statistics as one
// JSON object, as quilt.json and vpe quilt --json give them.
std::string quiltLayoutJson(const QuiltTextureReport& report);

}  // namespace vpe::quilt
