// SPDX-License-Identifier: MIT
// Reading a device bundle (proto/BUNDLE.md): BundleView validates a bundle's bytes and points
// into them; BundleFile maps a file read-only and holds its BundleView. Meshes, textures and
// the low-rank bases are spans into the mapping, ready for GL upload; only the few numbers of
// calibrations (projector, camera), settings and model (its θs basis included) are decoded into
// plain structs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vpe/proto/bundle_contents.h"
#include "vpe/proto/bundle_format.h"

namespace vpe::proto {

struct MeshView {
    std::span<const float> positions;        // 3 per vertex, metres, object frame
    std::span<const float> normals;          // 3 per vertex, unit
    std::span<const float> uvs;              // 2 per vertex
    std::span<const std::uint32_t> indices;  // 3 per triangle, each < vertexCount()
    std::size_t vertexCount() const { return positions.size() / 3; }
    std::size_t triangleCount() const { return indices.size() / 3; }
};

// An RGBA16F 2D texture array: layer-major, rows top to bottom, 4 half floats per texel.
struct HalfLayers {
    int layers = 0;
    int width = 0;
    int height = 0;
    std::span<const std::uint16_t> halves;  // IEEE binary16 bits, layers·height·width·4
    std::size_t bytes() const { return halves.size_bytes(); }
};

enum class CoefficientEncoding { kFull, kLowRank };

// One coefficient map; C = BundleModel::coefficientsPerTexel(), values ordered as
// bundleCoefficientIndex().
struct CoefficientMapView {
    CoefficientEncoding encoding = CoefficientEncoding::kFull;
    int rank = 0;  // kLowRank: R; kFull: 0
    // kFull: ceil(C / 4) layers, value i in layer i / 4, component i % 4 (padding is zero).
    // kLowRank: ceil(R / 4) layers of weights w_r, r the same way.
    HalfLayers layers;
    std::span<const float> mean;   // kLowRank: μ, C values
    std::span<const float> basis;  // kLowRank: B_r at [r·C, (r + 1)·C)
    // Format 1.2, optional: the relief's detail normal per texel, x and y as binary16 bits at
    // [(row·width + x)·2, +2), rows from the top (proto/detail_normal.h; z = √(1 − x² − y²)).
    // Empty: no relief.
    std::span<const std::uint16_t> detailNormals;
    int bytesPerTexel() const { return layers.layers * 8; }  // the coefficients
};

struct RegionView {
    std::string_view name;
    CoefficientMapView coefficients;
};

enum class AlphaEncoding { kUnorm8, kFloat16 };

// One α layer per region, [region][row][x]; Σ α = 1 at every texel.
struct WeightPresetView {
    std::string_view name;
    AlphaEncoding encoding = AlphaEncoding::kUnorm8;
    int layers = 0;                         // the number of regions
    std::span<const std::uint8_t> unorm8;   // kUnorm8: α = value / 255
    std::span<const std::uint16_t> halves;  // kFloat16: binary16 bits
    int bytesPerTexel() const { return layers * (encoding == AlphaEncoding::kUnorm8 ? 1 : 2); }
};

// Format 1.4: the light measured on site, per projector pixel (BUNDLE.md, `Radiometry`).
struct RadiometryView {
    std::array<double, 9> mixing{};  // X, row-major, diagonal 1
    // Binary16 bits, [(row·width + x)·4, +4): r, g, b, 0 at the projector's width × height.
    std::span<const std::uint16_t> irradiance;  // F
    std::span<const std::uint16_t> floor;       // D
};

// Format 1.5: this projector's share of the light in a show of several (BUNDLE.md, `Blend`).
struct BlendView {
    int projectors = 1;  // how many light the object
    int index = 0;       // this one's, < projectors
    // Binary16 bits, [row·width + x] at the projector's width × height, each in [0, 1].
    std::span<const std::uint16_t> share;
};

struct BundleOpenOptions {
    // The CRC-32 pass reads every byte of the file. A device that verified the bundle once
    // after installing it may skip it; every structural check still runs, so a bad file is
    // still refused rather than read out of bounds.
    bool verifyChecksum = true;
};

class BundleView {
public:
    // Validates a whole bundle held in memory and returns a view into it (the bytes must
    // outlive the view). `bytes.data()` must be 64-byte aligned, as a mapping is; `name`
    // starts every error message. Throws BundleError on any problem, never reads out of
    // bounds, whatever the bytes.
    static BundleView parse(std::span<const std::byte> bytes, const std::string& name,
                            const BundleOpenOptions& options = {});

    const BundleHeader& header() const { return header_; }
    bool checksumVerified() const { return checksumVerified_; }
    // Verifies the checksum now (when opened without); throws BundleError on a mismatch.
    void verifyChecksum();

    const MeshView& mesh() const { return mesh_; }
    const ProjectorCalibration& projector() const { return projector_; }
    // Format 1.3, optional: the installation's camera (the lamp tracker's), object frame →
    // camera frame in the projector's conventions; checked like the projector. Empty: the
    // bundle carries none (every bundle before 1.3).
    const std::optional<ProjectorCalibration>& camera() const { return camera_; }
    // Format 1.4, optional: the light measured on site; empty: the settings' assumptions.
    const std::optional<RadiometryView>& radiometry() const { return radiometry_; }
    // Format 1.5, optional: the projector's share among several; empty: the only projector.
    const std::optional<BlendView>& blend() const { return blend_; }
    const RenderSettings& settings() const { return settings_; }
    const BundleModel& model() const { return model_; }
    int textureWidth() const { return textureWidth_; }
    int textureHeight() const { return textureHeight_; }
    // Sampling wraps in u (format 1.2): the textures tile around the screen object.
    bool textureWrapsU() const { return textureWrapsU_; }
    const std::vector<RegionView>& regions() const { return regions_; }
    const std::optional<CoefficientMapView>& composed() const { return composed_; }
    const std::vector<WeightPresetView>& presets() const { return presets_; }

    std::span<const std::byte> bytes() const { return bytes_; }
    const std::string& name() const { return name_; }

private:
    friend class BundleDecoder;
    BundleView() = default;

    std::span<const std::byte> bytes_;
    std::string name_;
    BundleHeader header_;
    bool checksumVerified_ = false;
    MeshView mesh_;
    ProjectorCalibration projector_;
    std::optional<ProjectorCalibration> camera_;
    std::optional<RadiometryView> radiometry_;
    std::optional<BlendView> blend_;
    RenderSettings settings_;
    BundleModel model_;
    int textureWidth_ = 0;
    int textureHeight_ = 0;
    bool textureWrapsU_ = false;
    std::vector<RegionView> regions_;
    std::optional<CoefficientMapView> composed_;
    std::vector<WeightPresetView> presets_;
};

// A bundle file mapped read-only. Moving it keeps the views valid (the mapping stays put).
class BundleFile {
public:
    // Maps and validates `path`; errors name the path as given.
    static BundleFile open(const std::filesystem::path& path,
                           const BundleOpenOptions& options = {});
    ~BundleFile();
    BundleFile(BundleFile&& other) noexcept;
    BundleFile& operator=(BundleFile&& other) noexcept;
    BundleFile(const BundleFile&) = delete;
    BundleFile& operator=(const BundleFile&) = delete;

    const BundleView& view() const { return view_; }
    BundleView& view() { return view_; }
    const BundleView* operator->() const { return &view_; }

private:
    BundleFile(void* mapping, std::size_t size, BundleView view);
    void unmap();

    void* mapping_ = nullptr;  // owned: munmap on destruction
    std::size_t size_ = 0;
    BundleView view_;
};

}  // namespace vpe::proto
