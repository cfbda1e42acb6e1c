// SPDX-License-Identifier: MIT
// The model file: one multi-channel OpenEXR image holding, per pixel, the Fourier BRDF
// coefficients of each colour channel, the normal, the fit's residual RMS and a validity
// flag. Channel names (documented in docs/model-file.md) group each coefficient as an RGB
// layer — "kd.R kd.G kd.B", "a0.*", "a1.*", "b1.*", ... — so standard EXR viewers show
// any coefficient as a picture. Written and read in bands of rows.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vpe/capture/geometry_calibration.h"
#include "vpe/model/rti_basis.h"

namespace vpe::model {

// The channel type of a model file. Half floats keep 11 significant bits (relative error
// ≤ 2⁻¹¹ ≈ 4.9e-4 for |x| ≥ 2⁻¹⁴, absolute ≤ 2⁻²⁵ below): on the fits measured it changes
// nothing visible, halves the file and its writing time (docs/model-file.md). Float is exact.
enum class ModelStorage { kFloat, kHalf };

// "half" / "float", as the commands' --storage option spells them.
const char* storageName(ModelStorage storage);

struct ModelInfo {
    int width = 0;
    int height = 0;
    int harmonics = 0;
    double lambda = 0;
    int samples = 0;  // images the fit used
    // "paper" or "extended" (Fourier BRDFs), or an RTI basis fitted for comparison: "ptm",
    // "hsh" with `terms` coefficients per channel (model/rti_basis.h).
    std::string variant = "paper";
    int terms = 0;
    std::string capture;  // what was fitted (for people reading the header)
    // The capture geometry the model was fitted under (extended variant): evaluation of
    // another capture from the same dome applies it too.
    capture::GeometryCalibration calibration;
    // The side of a texel on the captured surface, millimetres (0: unknown): from the capture's
    // manifest through vpe fit; a quilted texture keeps its source's.
    double texelMm = 0;
    // The texture tiles in u: its last column continues into its first (vpe quilt on a screen
    // object whose u wraps).
    bool tilesU = false;
    // As read: the type of the file's coefficient channels. As written: the type of every
    // channel. Float unless asked, so no caller loses precision without choosing to.
    ModelStorage storage = ModelStorage::kFloat;
    // The relief as a detail normal map (channels detail.X/Y/Z): fitted models whose normals
    // had relief, and the textures quilted and composed from them. Without it: no relief.
    bool detailNormals = false;
    bool hasTransport() const { return variant == "extended"; }
    bool isBrdf() const { return variant == "paper" || variant == "extended"; }
    std::optional<RtiBasis> rtiBasis() const;  // for "ptm" and "hsh"
    int coefficientCount() const;              // per colour channel
};

// The header of a Fourier BRDF model of this grid and expansion (M = harmonics, λ = lambda),
// fitted on `samples` images: what every writer of a model states first; the caller adds
// the rest it knows.
ModelInfo fourierModelInfo(int width, int height, int harmonics, double lambda, int samples);

// "kd", "a0", "a1", "b1", ..., in coefficient order.
std::string coefficientName(int index);
// A model's coefficient layer names: the Fourier BRDF's above, or an RTI basis's "c00" ….
std::string coefficientName(const ModelInfo& info, int index);

// A band of model rows, pixel-major.
struct ModelRows {
    int width = 0;
    int rows = 0;
    int coefficients = 0;             // 2M + 2 per colour channel
    std::vector<float> coefficient;   // [row][x][channel][k]
    std::vector<float> normal;        // [row][x][3]
    std::vector<float> rms;           // [row][x][3], linear, normalized to unit irradiance
    std::vector<std::uint8_t> valid;  // [row][x]
    // Extended variant only: the capture-specific light transport T, kTransportValues per
    // pixel (model/light_transport.h); empty for the paper's model.
    std::vector<float> transport;  // [row][x][channel][term]
    // With ModelInfo::detailNormals: the relief's detail normal per pixel, tangent space
    // (proto/detail_normal.h; docs/model-file.md), (0, 0, 1) where flat; empty without.
    std::vector<float> detail;  // [row][x][3]

    void resize(int w, int r, int k, bool withTransport = false, bool withDetail = false);
    std::size_t pixel(int row, int x) const { return static_cast<std::size_t>(row) * width + x; }
    const float* coefficientsAt(int row, int x, int channel) const {
        return coefficient.data() + (pixel(row, x) * 3 + channel) * coefficients;
    }
};

class ModelWriter {
public:
    // Writes to a temporary file next to `path`; finish() moves it into place. Channels are
    // half or float as info.storage says; a value beyond the half range (±65504) is refused
    // with InputError naming the pixel, never written as infinity. Rows are packed on
    // `threads` threads.
    ModelWriter(const std::filesystem::path& path, const ModelInfo& info, unsigned threads = 1);
    ~ModelWriter();
    ModelWriter(const ModelWriter&) = delete;
    ModelWriter& operator=(const ModelWriter&) = delete;

    void writeRows(int rowBegin, const ModelRows& rows);
    void finish();

private:
    [[noreturn]] void reportHalfOverflow(int rowBegin, int row, const ModelRows& rows) const;

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// What a reader accepts: a Fourier BRDF (what rendering, segmentation, quilting and the bake
// need), or also an RTI basis fitted for comparison (what `vpe eval` scores).
enum class ModelKinds { kBrdf, kAny };

class ModelReader {
public:
    // Checks that the file is a vpe model of an accepted kind and names what is wrong if not.
    explicit ModelReader(const std::filesystem::path& path,
                         ModelKinds accepted = ModelKinds::kBrdf);
    ~ModelReader();
    ModelReader(const ModelReader&) = delete;
    ModelReader& operator=(const ModelReader&) = delete;

    const ModelInfo& info() const;
    void readRows(int rowBegin, int rows, ModelRows& out);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vpe::model
