// SPDX-License-Identifier: MIT
// The `vpe quilt` pipeline.
#include "vpe/quilt/texture_quilt.h"

#include <chrono>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/seconds_since.h"
#include "vpe/image/image_file.h"
#include "vpe/model/coefficient_image.h"
#include "vpe/model/fourier_model_file.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/quilt/quilt_folder.h"
#include "vpe/scene/procedural_vase.h"
#include "vpe/scene/screen_mesh.h"
#include "vpe/segment/label_map.h"

namespace vpe::quilt {

namespace {

using Clock = std::chrono::steady_clock;

nlohmann::json stretchJson(const scene::TexelStretch& s) {
    return {{"worst", s.worst},
            {"worst_uv", {s.worstU, s.worstV}},
            {"mean", s.mean},
            {"median", s.median},
            {"p95", s.p95},
            {"texel_u_mm", s.texelUMm},
            {"texel_v_mm", s.texelVMm}};
}

nlohmann::json layoutJson(const QuiltTextureReport& report) {
    nlohmann::json json;
    json["width"] = report.width;
    json["height"] = report.height;
    json["size_auto"] = report.autoSize;
    json["wrap_u"] = report.wrapU;
    json["texel_mm"] = report.texelMm;
    json["mesh"] = report.mesh;
    json["mesh_wraps_u"] = report.meshWrapsU;
    json["stretch"] = stretchJson(report.stretch);
    return json;
}

void checkQuiltOptions(const QuiltTextureOptions& options) {
    if (options.width.has_value() != options.height.has_value() ||
        (options.width && (*options.width <= 0 || *options.height <= 0 || *options.width > 16384 ||
                           *options.height > 16384))) {
        throw common::InputError("--size must be auto or between 1x1 and 16384x16384");
    }
    if (options.texelMm && !(*options.texelMm > 0 && std::isfinite(*options.texelMm))) {
        throw common::InputError("--texel-mm must be a positive number of millimetres");
    }
}

// Sizing: the screen object's surface lengths give the size (unless it is given), its seam
// the wrapping; the report takes the layout and the texels' stretch on the object.
void chooseLayout(const QuiltTextureOptions& options, const model::ModelInfo& info,
                  QuiltTextureReport& report) {
    scene::ScreenMesh mesh;
    if (options.mesh.empty()) {
        mesh = scene::makeProceduralVase();
        report.mesh = "the built-in vase";
    } else {
        scene::ScreenMeshLoadOptions load;
        load.metresPerUnit = options.meshMetresPerUnit;
        mesh = scene::loadScreenMesh(options.mesh, load);
        report.mesh = options.mesh.string();
    }
    const scene::SurfaceScale surface =
        measureSurfaceScale(mesh, options.mesh.empty() ? "vase" : report.mesh.c_str());
    report.meshWrapsU = surface.wrapsU;
    report.texelMm = options.texelMm.value_or(info.texelMm);
    if (options.width) {
        report.width = *options.width;
        report.height = *options.height;
    } else {
        if (!(report.texelMm > 0)) {
            throw common::InputError(options.model,
                                     "--size auto: the model states no texel size (its "
                                     "capture manifest has no texel_mm); give --texel-mm");
        }
        const scene::AutoTextureSize size =
            scene::chooseTextureSize(surface, report.texelMm, kMaxAutoSide);
        report.width = size.width;
        report.height = size.height;
        report.autoSize = true;
    }
    report.stretch = scene::measureTexelStretch(surface, report.width, report.height);
    report.wrapU =
        options.wrap == WrapMode::kOn || (options.wrap == WrapMode::kAuto && surface.wrapsU);
}

// What the regions are quilted from: the model, every coefficient of every channel as one
// vector per pixel, and the labels (pixels without a valid fit never a source).
struct QuiltSource {
    model::CoefficientImage texture;
    std::vector<std::uint8_t> labels;
    int regions = 0;
};

// Loading.
QuiltSource loadSource(model::ModelReader& reader, const QuiltTextureOptions& options) {
    const model::ModelInfo& info = reader.info();
    QuiltSource source;
    source.texture = model::readCoefficientImage(reader);
    source.labels = segment::readLabelImage(options.labels, info.width, info.height).values;
    for (std::size_t p = 0; p < source.labels.size(); ++p) {
        if (!source.texture.valid[p]) {
            source.labels[p] = segment::LabelMap::kNoLabel;  // no fit: never a source
        } else if (source.labels[p] != segment::LabelMap::kNoLabel) {
            source.regions = std::max(source.regions, source.labels[p] + 1);
        }
    }
    if (source.regions == 0) {
        throw common::InputError(options.labels, "no labelled pixel has a valid fit");
    }
    return source;
}

std::size_t regionPixels(const QuiltSource& source, int region,
                         const std::filesystem::path& labels) {
    std::size_t pixels = 0;
    for (std::uint8_t l : source.labels) {
        pixels += l == region ? 1 : 0;
    }
    if (pixels == 0) {
        throw common::InputError(
            labels, "region " + std::to_string(region) + " has no pixel (labels must be 0..K-1)");
    }
    return pixels;
}

// Writing one region: its map (region<k>.exr, the copied texels' coefficients and relief) and
// its positions (positions<k>.exr) into `folder`. Returns the quilted coefficients, one
// vector per output pixel, for the seam's statistics.
std::vector<float> writeRegion(const std::filesystem::path& folder, int region,
                               const RegionQuilt& quilt, const QuiltSource& source,
                               const model::ModelInfo& info, const QuiltTextureOptions& options,
                               int width, int height) {
    const model::CoefficientImage& texels = source.texture;
    model::ModelInfo texture = info;
    texture.width = width;
    texture.height = height;
    texture.tilesU = quilt.wrapU;  // texelMm: the source's, as copied pixels keep their size
    texture.variant = "paper";     // a texture holds materials only: no capture transport
    texture.calibration = {};
    texture.storage = options.storage.value_or(info.storage);
    texture.capture =
        "vpe quilt of " + options.model.string() + ", region " + std::to_string(region);
    model::ModelWriter writer(quilt::regionMapPath(folder, region), texture,
                              options.settings.threads);
    constexpr int kBand = 64;
    quilt::PositionMap positions;
    positions.width = width;
    positions.height = height;
    positions.sourceX = quilt.sourceX;
    positions.sourceY = quilt.sourceY;
    model::ModelRows band;
    std::vector<float> quilted(static_cast<std::size_t>(width) * height * texels.dims);
    for (int y0 = 0; y0 < height; y0 += kBand) {
        const int bandRows = std::min(kBand, height - y0);
        if (band.rows != bandRows) {
            band.resize(width, bandRows, texels.dims / 3, false, texture.detailNormals);
        }
        // Every pixel's coefficients are overwritten, on all threads; normal, rms and the
        // flag are the same for every band.
        common::parallelFor(
            static_cast<std::size_t>(bandRows), 1, options.settings.threads,
            [&](std::size_t begin, std::size_t end) {
                for (std::size_t r = begin; r < end; ++r) {
                    for (int x = 0; x < width; ++x) {
                        const std::size_t o = (static_cast<std::size_t>(y0) + r) * width + x;
                        const std::size_t p = band.pixel(static_cast<int>(r), x);
                        const int sx = quilt.sourceX[o], sy = quilt.sourceY[o];
                        const float* texel = texels.at(sx, sy);
                        std::copy_n(texel, texels.dims,
                                    band.coefficient.begin() + static_cast<long>(p) * texels.dims);
                        std::copy_n(texel, texels.dims,
                                    quilted.begin() + static_cast<long>(o) * texels.dims);
                        // The relief goes with its texel's coefficients.
                        if (texture.detailNormals) {
                            std::copy_n(
                                texels.detail.begin() + static_cast<long>(texels.pixel(sx, sy) * 3),
                                3, band.detail.begin() + static_cast<long>(p * 3));
                        }
                        band.normal[p * 3 + 2] = 1.0f;
                        band.valid[p] = 1;
                    }
                }
            });
        writer.writeRows(y0, band);
    }
    writer.finish();
    quilt::writePositionMap(quilt::positionsPath(folder, region), positions, region);
    return quilted;
}

// quilt.json's description of the whole quilt, its regions still to come.
nlohmann::json quiltDescription(const QuiltTextureOptions& options, const model::ModelInfo& info,
                                const QuiltTextureReport& report) {
    nlohmann::json description;
    description["model"] = options.model.string();
    description["labels"] = options.labels.string();
    description.update(layoutJson(report));
    description["harmonics"] = info.harmonics;
    description["channels"] = report.channels;
    description["seed"] = options.settings.seed;
    description["tolerance"] = options.settings.tolerance;
    description["regions"] = nlohmann::json::array();
    return description;
}

nlohmann::json regionJson(const RegionReport& region, const RegionQuilt& quilt) {
    return {{"region", region.region},        {"source_pixels", region.sourcePixels},
            {"candidates", quilt.candidates}, {"block", quilt.block},
            {"overlap", quilt.overlap},       {"components", quilt.components},
            {"blocks", quilt.blocks},         {"seam", quilt::seamJson(region.seam)},
            {"seconds", region.seconds}};
}

}  // namespace

std::string quiltLayoutJson(const QuiltTextureReport& report) {
    nlohmann::json json = layoutJson(report);
    json["seams"] = nlohmann::json::array();
    for (const RegionReport& region : report.regions) {
        json["seams"].push_back(quilt::seamJson(region.seam));
    }
    return json.dump();
}

// `vpe quilt` (docs/quilting.md): sizing, loading, then quilting and writing a region at a time.
QuiltTextureReport quiltTexture(const QuiltTextureOptions& options) {
    const auto start = Clock::now();
    checkQuiltOptions(options);
    QuiltTextureReport report;
    model::ModelReader reader(options.model);
    const model::ModelInfo info = reader.info();
    chooseLayout(options, info, report);
    QuiltSettings settings = options.settings;
    settings.wrapU = report.wrapU;
    const int width = report.width, height = report.height;
    const QuiltSource source = loadSource(reader, options);
    report.channels = source.texture.dims;
    report.loadSeconds = common::secondsSince(start);

    common::AtomicFolder folder(options.out, "quilt.json", "vpe quilt");
    const std::filesystem::path& partial = folder.temporaryPath();
    nlohmann::json description = quiltDescription(options, info, report);
    // Two steps per region: quilting it, writing its maps.
    common::ProgressBar progress("quilt", 2 * static_cast<std::size_t>(source.regions));
    auto showPhase = [&](const std::string& what) {
        progress.setPhase(what, {{"load", report.loadSeconds},
                                 {"quilt", report.quiltSeconds},
                                 {"write", report.writeSeconds}});
    };
    auto regionName = [&](int region) {
        return "region " + std::to_string(region + 1) + " of " + std::to_string(source.regions);
    };
    for (int region = 0; region < source.regions; ++region) {
        RegionReport regionReport;
        regionReport.region = region;
        regionReport.sourcePixels = regionPixels(source, region, options.labels);
        showPhase("quilting " + regionName(region));
        const auto quiltStart = Clock::now();
        RegionQuilt quilt =
            quiltRegion(source.texture, source.labels, region, width, height, settings);
        regionReport.seconds = common::secondsSince(quiltStart);
        report.quiltSeconds += regionReport.seconds;
        progress.advance();

        showPhase("writing " + regionName(region));
        const auto writeStart = Clock::now();
        const std::vector<float> quilted =
            writeRegion(partial, region, quilt, source, info, options, width, height);
        report.writeSeconds += common::secondsSince(writeStart);
        if (width >= 3) {
            regionReport.seam = quilt::measureSeam(quilted, width, height, report.channels);
        }
        description["regions"].push_back(regionJson(regionReport, quilt));
        regionReport.seam.columnSteps.clear();
        quilt.sourceX.clear();
        quilt.sourceY.clear();
        regionReport.quilt = std::move(quilt);
        report.regions.push_back(std::move(regionReport));
        progress.advance();
    }
    showPhase("done");
    progress.finish();
    report.seconds = common::secondsSince(start);
    description["seconds"] = report.seconds;
    proto::writeTextFileAtomically(partial / "quilt.json", description.dump(1) + "\n");
    folder.commit();
    return report;
}

}  // namespace vpe::quilt
