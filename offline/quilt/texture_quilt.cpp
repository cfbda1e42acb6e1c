// SPDX-License-Identifier: MIT
// The `vpe quilt` pipeline.
#include "quilt/texture_quilt.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "common/atomic_folder.h"
#include "common/atomic_output.h"
#include "common/input_error.h"
#include "common/progress_bar.h"
#include "image/image_file.h"
#include "model/fourier_model_file.h"
#include "segment/label_map.h"
#include "texture/quilt_folder.h"

namespace vpe::quilt {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

QuiltTextureReport quiltTexture(const QuiltTextureOptions& options) {
    const auto start = Clock::now();
    if (options.width <= 0 || options.height <= 0 || options.width > 16384 ||
        options.height > 16384) {
        throw InputError("--size must be between 1x1 and 16384x16384");
    }
    QuiltTextureReport report;
    // The source: every coefficient of every channel, one vector per pixel.
    ModelReader reader(options.model);
    const ModelInfo info = reader.info();
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
    report.loadSeconds = since(start);

    const std::filesystem::path out = options.out;
    AtomicFolder folder(out, "quilt.json", "vpe quilt");
    const std::filesystem::path& partial = folder.temporaryPath();

    nlohmann::json description;
    description["model"] = options.model.string();
    description["labels"] = options.labels.string();
    description["width"] = options.width;
    description["height"] = options.height;
    description["harmonics"] = info.harmonics;
    description["channels"] = source.channels;
    description["seed"] = options.settings.seed;
    description["tolerance"] = options.settings.tolerance;
    description["regions"] = nlohmann::json::array();
    // Two steps per region: quilting it, writing its maps.
    ProgressBar progress("quilt", 2 * static_cast<std::size_t>(regions));
    auto showPhase = [&](const std::string& what) {
        char text[160];
        std::snprintf(text, sizeof text, "%s  (load %.1f s, quilt %.1f s, write %.1f s)",
                      what.c_str(), report.loadSeconds, report.quiltSeconds, report.writeSeconds);
        progress.setPhase(text);
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
        RegionQuilt quilt =
            quiltRegion(source, labels, region, options.width, options.height, options.settings);
        regionReport.seconds = since(quiltStart);
        report.quiltSeconds += regionReport.seconds;
        progress.advance();
        showPhase("writing " + regionName(region));

        const auto writeStart = Clock::now();
        ModelInfo texture = info;
        texture.width = options.width;
        texture.height = options.height;
        texture.variant = "paper";  // a texture holds materials only: no capture transport
        texture.calibration = {};
        texture.capture =
            "vpe quilt of " + options.model.string() + ", region " + std::to_string(region);
        ModelWriter writer(texture::regionMapPath(partial, region), texture);
        constexpr int kBand = 64;
        texture::PositionMap positions;
        positions.width = options.width;
        positions.height = options.height;
        positions.sourceX = quilt.sourceX;
        positions.sourceY = quilt.sourceY;
        ModelRows band;
        for (int y0 = 0; y0 < options.height; y0 += kBand) {
            const int bandRows = std::min(kBand, options.height - y0);
            band.resize(options.width, bandRows, rows.coefficients);
            for (int r = 0; r < bandRows; ++r) {
                for (int x = 0; x < options.width; ++x) {
                    const std::size_t o = static_cast<std::size_t>(y0 + r) * options.width + x;
                    const int sx = quilt.sourceX[o], sy = quilt.sourceY[o];
                    const std::size_t p = band.pixel(r, x);
                    std::copy_n(source.at(sx, sy), source.channels,
                                band.coefficient.begin() + static_cast<long>(p) * source.channels);
                    band.normal[p * 3 + 2] = 1.0f;
                    band.valid[p] = 1;
                }
            }
            writer.writeRows(y0, band);
        }
        writer.finish();
        texture::writePositionMap(texture::positionsPath(partial, region), positions, region);
        report.writeSeconds += since(writeStart);

        description["regions"].push_back({{"region", region},
                                          {"source_pixels", regionReport.sourcePixels},
                                          {"candidates", quilt.candidates},
                                          {"block", quilt.block},
                                          {"overlap", quilt.overlap},
                                          {"components", quilt.components},
                                          {"blocks", quilt.blocks},
                                          {"seconds", regionReport.seconds}});
        quilt.sourceX.clear();
        quilt.sourceY.clear();
        regionReport.quilt = std::move(quilt);
        report.regions.push_back(std::move(regionReport));
        progress.advance();
    }
    showPhase("done");
    progress.finish();
    report.seconds = since(start);
    description["seconds"] = report.seconds;
    writeTextFileAtomically(partial / "quilt.json", description.dump(1) + "\n");
    folder.commit();
    return report;
}

}  // namespace vpe::quilt
