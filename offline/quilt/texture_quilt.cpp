// SPDX-License-Identifier: MIT
// The `vpe quilt` pipeline.
#include "vpe/quilt/texture_quilt.h"

#include <chrono>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "vpe/common/atomic_folder.h"
#include "vpe/common/atomic_output.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/common/progress_bar.h"
#include "vpe/common/seconds_since.h"
#include "vpe/image/image_file.h"
#include "vpe/model/fourier_model_file.h"
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

}  // namespace

std::string quiltLayoutJson(const QuiltTextureReport& report) {
    nlohmann::json json = layoutJson(report);
    json["seams"] = nlohmann::json::array();
    for (const RegionReport& region : report.regions) {
        json["seams"].push_back(quilt::seamJson(region.seam));
    }
    return json.dump();
}

QuiltTextureReport quiltTexture(const QuiltTextureOptions& options) {
    const auto start = Clock::now();
    if (options.width.has_value() != options.height.has_value() ||
        (options.width && (*options.width <= 0 || *options.height <= 0 || *options.width > 16384 ||
                           *options.height > 16384))) {
        throw InputError("--size must be auto or between 1x1 and 16384x16384");
    }
    if (options.texelMm && !(*options.texelMm > 0 && std::isfinite(*options.texelMm))) {
        throw InputError("--texel-mm must be a positive number of millimetres");
    }
    QuiltTextureReport report;
    // The source: every coefficient of every channel, one vector per pixel.
    ModelReader reader(options.model);
    const ModelInfo info = reader.info();

    // The screen object: its surface lengths give the size, its seam the wrapping.
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
            throw InputError(options.model,
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
    QuiltSettings settings = options.settings;
    settings.wrapU = report.wrapU;
    const int width = report.width, height = report.height;

    ModelRows rows;
    reader.readRows(0, info.height, rows);
    SourceTexture source;
    source.width = info.width;
    source.height = info.height;
    source.channels = 3 * rows.coefficients;
    source.values = rows.coefficient;  // [pixel][channel][k] is already one vector per pixel
    report.channels = source.channels;
    std::vector<std::uint8_t> labels =
        readLabelImage(options.labels, info.width, info.height).values;
    int regions = 0;
    for (std::size_t p = 0; p < labels.size(); ++p) {
        if (!rows.valid[p]) {
            labels[p] = LabelMap::kNoLabel;  // no fit: never a source
        } else if (labels[p] != LabelMap::kNoLabel) {
            regions = std::max(regions, labels[p] + 1);
        }
    }
    if (regions == 0) {
        throw InputError(options.labels, "no labelled pixel has a valid fit");
    }
    report.loadSeconds = secondsSince(start);

    const std::filesystem::path out = options.out;
    AtomicFolder folder(out, "quilt.json", "vpe quilt");
    const std::filesystem::path& partial = folder.temporaryPath();

    nlohmann::json description;
    description["model"] = options.model.string();
    description["labels"] = options.labels.string();
    description.update(layoutJson(report));
    description["harmonics"] = info.harmonics;
    description["channels"] = source.channels;
    description["seed"] = options.settings.seed;
    description["tolerance"] = options.settings.tolerance;
    description["regions"] = nlohmann::json::array();
    // Two steps per region: quilting it, writing its maps.
    ProgressBar progress("quilt", 2 * static_cast<std::size_t>(regions));
    auto showPhase = [&](const std::string& what) {
        progress.setPhase(what, {{"load", report.loadSeconds},
                                 {"quilt", report.quiltSeconds},
                                 {"write", report.writeSeconds}});
    };
    auto regionName = [regions](int region) {
        return "region " + std::to_string(region + 1) + " of " + std::to_string(regions);
    };
    for (int region = 0; region < regions; ++region) {
        RegionReport regionReport;
        regionReport.region = region;
        for (std::uint8_t l : labels) {
            regionReport.sourcePixels += l == region ? 1 : 0;
        }
        if (regionReport.sourcePixels == 0) {
            throw InputError(options.labels, "region " + std::to_string(region) +
                                                 " has no pixel (labels must be 0..K-1)");
        }
        showPhase("quilting " + regionName(region));
        const auto quiltStart = Clock::now();
        RegionQuilt quilt = quiltRegion(source, labels, region, width, height, settings);
        regionReport.seconds = secondsSince(quiltStart);
        report.quiltSeconds += regionReport.seconds;
        progress.advance();
        showPhase("writing " + regionName(region));

        const auto writeStart = Clock::now();
        ModelInfo texture = info;
        texture.width = width;
        texture.height = height;
        texture.tilesU = quilt.wrapU;  // texelMm: the source's, as copied pixels keep their size
        texture.variant = "paper";     // a texture holds materials only: no capture transport
        texture.calibration = {};
        texture.storage = options.storage.value_or(info.storage);
        texture.capture =
            "vpe quilt of " + options.model.string() + ", region " + std::to_string(region);
        ModelWriter writer(quilt::regionMapPath(partial, region), texture,
                           options.settings.threads);
        constexpr int kBand = 64;
        quilt::PositionMap positions;
        positions.width = width;
        positions.height = height;
        positions.sourceX = quilt.sourceX;
        positions.sourceY = quilt.sourceY;
        ModelRows band;
        std::vector<float> quilted(static_cast<std::size_t>(width) * height * source.channels);
        for (int y0 = 0; y0 < height; y0 += kBand) {
            const int bandRows = std::min(kBand, height - y0);
            if (band.rows != bandRows) {
                band.resize(width, bandRows, rows.coefficients, false, texture.detailNormals);
            }
            // Every pixel's coefficients are overwritten, on all threads; normal, rms and the
            // flag are the same for every band.
            parallelFor(
                static_cast<std::size_t>(bandRows), 1, options.settings.threads,
                [&](std::size_t begin, std::size_t end) {
                    for (std::size_t r = begin; r < end; ++r) {
                        for (int x = 0; x < width; ++x) {
                            const std::size_t o = (static_cast<std::size_t>(y0) + r) * width + x;
                            const std::size_t p = band.pixel(static_cast<int>(r), x);
                            const int sx = quilt.sourceX[o], sy = quilt.sourceY[o];
                            const float* texel = source.at(sx, sy);
                            std::copy_n(
                                texel, source.channels,
                                band.coefficient.begin() + static_cast<long>(p) * source.channels);
                            std::copy_n(texel, source.channels,
                                        quilted.begin() + static_cast<long>(o) * source.channels);
                            // The relief goes with its texel's coefficients.
                            if (texture.detailNormals) {
                                std::copy_n(
                                    rows.detail.begin() + static_cast<long>(rows.pixel(sy, sx) * 3),
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
        quilt::writePositionMap(quilt::positionsPath(partial, region), positions, region);
        report.writeSeconds += secondsSince(writeStart);
        if (width >= 3) {
            regionReport.seam = quilt::measureSeam(quilted, width, height, source.channels);
        }

        description["regions"].push_back({{"region", region},
                                          {"source_pixels", regionReport.sourcePixels},
                                          {"candidates", quilt.candidates},
                                          {"block", quilt.block},
                                          {"overlap", quilt.overlap},
                                          {"components", quilt.components},
                                          {"blocks", quilt.blocks},
                                          {"seam", quilt::seamJson(regionReport.seam)},
                                          {"seconds", regionReport.seconds}});
        regionReport.seam.columnSteps.clear();
        quilt.sourceX.clear();
        quilt.sourceY.clear();
        regionReport.quilt = std::move(quilt);
        report.regions.push_back(std::move(regionReport));
        progress.advance();
    }
    showPhase("done");
    progress.finish();
    report.seconds = secondsSince(start);
    description["seconds"] = report.seconds;
    writeTextFileAtomically(partial / "quilt.json", description.dump(1) + "\n");
    folder.commit();
    return report;
}

}  // namespace vpe::quilt
