// SPDX-License-Identifier: MIT
// Writes a device bundle (proto/BUNDLE.md) from plain arrays: mesh, projector (and camera)
// calibration, render settings, and coefficient and weight textures as floats, which it encodes as
// half floats (or 8-bit weights) laid out for direct GL upload.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vpe/proto/bundle.h"

namespace vpe::bake {

struct BundleMesh {
    std::vector<float> positions;        // 3 per vertex, metres, object frame
    std::vector<float> normals;          // 3 per vertex, unit
    std::vector<float> uvs;              // 2 per vertex, (0, 0) the textures' top-left corner
    std::vector<std::uint32_t> indices;  // 3 per triangle
};

// A coefficient map of the bundle's texture size; C = model.coefficientsPerTexel() values per
// texel, ordered by proto::bundleCoefficientIndex(), texels row by row from the top.
struct CoefficientMapData {
    proto::CoefficientEncoding encoding = proto::CoefficientEncoding::kFull;
    std::vector<float> coefficients;  // kFull: C per texel
    // kLowRank: coefficient(x) = mean + Σ_r weights(x)[r] · basis[r].
    int rank = 0;
    std::vector<float> mean;     // C values
    std::vector<float> basis;    // rank × C values, basis vector r at [r·C, (r + 1)·C)
    std::vector<float> weights;  // rank per texel
    // The relief (format 1.2): the detail normal's x and y per texel (proto/detail_normal.h),
    // x² + y² ≤ 1; empty: none.
    std::vector<float> detailNormals;
};

struct BundleRegion {
    std::string name;
    CoefficientMapData coefficients;
};

// One α map per region, [region][row][x]; Σ α = 1 at every texel (to 1e-3; the writer
// normalizes exactly, so that 8-bit weights add up to 255).
struct WeightPreset {
    std::string name;  // unique, not empty
    proto::AlphaEncoding encoding = proto::AlphaEncoding::kUnorm8;
    std::vector<float> alpha;
};

// Format 1.4: the light measured on site (vpe radiometry), per projector pixel.
struct BundleRadiometry {
    std::array<double, 9> mixing{1, 0, 0, 0, 1, 0, 0, 0, 1};  // X, diagonal 1, invertible
    std::vector<float> irradiance;  // F: projector width·height·3, finite, ≥ 0
    std::vector<float> floor;       // D: likewise
};

// Format 1.5: this projector's share of the light among several projectors on one object.
struct BundleBlend {
    int projectors = 1;        // how many light the object
    int index = 0;             // this one's
    std::vector<float> share;  // projector width·height, each in [0, 1]
};

struct BundleContents {
    BundleMesh mesh;
    proto::ProjectorCalibration projector;
    // Format 1.3: the installation's camera (object frame → camera, the projector's
    // conventions), for the device's lamp tracker; empty: the field stays absent.
    std::optional<proto::ProjectorCalibration> camera;
    // Format 1.4: the measured light; settings.response is then the response above black.
    std::optional<BundleRadiometry> radiometry;
    // Format 1.5: the share of the light this projector gives in a show of several.
    std::optional<BundleBlend> blend;
    proto::RenderSettings settings;
    proto::BundleModel model;  // M, λ and the θs basis (empty: none, rendered exactly)
    int textureWidth = 0;      // 1..4096
    int textureHeight = 0;
    bool textureWrapsU = false;  // the textures tile in u: the device's sampling wraps
    std::vector<BundleRegion> regions;
    std::optional<CoefficientMapData> composed;
    std::vector<WeightPreset> presets;
};

struct BundleWriteResult {
    std::uint64_t bytes = 0;
    std::uint32_t checksum = 0;
};

// Writes `contents` to a temporary file beside `path`, reads it back through the device
// reader, and only then renames it into place: on any error nothing is left behind. Contents a
// device would refuse (sizes that disagree, values that are not finite or do not fit a half
// float, textures over 4096, a non-monotone response, ...) throw InputError naming `path` and
// the field.
BundleWriteResult writeBundle(const std::filesystem::path& path, const BundleContents& contents);

}  // namespace vpe::bake
