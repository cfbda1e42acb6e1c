// SPDX-License-Identifier: MIT
// What vpe radiometry writes: the maps as OpenEXR, the response as the CSV vpe bake --response
// reads, the rest as JSON, and a contact sheet.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/quantile.h"
#include "vpe/image/contact_sheet.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/srgb.h"
#include "vpe/radiometry/projector_radiometry.h"

namespace vpe::radiometry {

namespace {

nlohmann::json arrayJson(const auto& values) {
    nlohmann::json json = nlohmann::json::array();
    for (const double v : values) {
        json.push_back(v);
    }
    return json;
}

template <std::size_t N>
std::array<double, N> arrayOf(const nlohmann::json& json, const std::filesystem::path& path,
                              const char* key) {
    if (!json.contains(key) || !json[key].is_array() || json[key].size() != N) {
        throw common::InputError(path,
                                 std::string(key) + ": expected " + std::to_string(N) + " numbers");
    }
    std::array<double, N> values{};
    for (std::size_t i = 0; i < N; ++i) {
        if (!json[key][i].is_number()) {
            throw common::InputError(path, std::string(key) + ": expected numbers");
        }
        values[i] = json[key][i].get<double>();
    }
    return values;
}

// Like arrayOf, but null (what a NaN is written as: a value the capture could not measure) reads
// as NaN, and a file without the key as NaN too.
template <std::size_t N>
std::array<double, N> measuredArrayOf(const nlohmann::json& json, const std::filesystem::path& path,
                                      const char* key) {
    std::array<double, N> values{};
    values.fill(std::numeric_limits<double>::quiet_NaN());
    if (!json.contains(key)) {
        return values;
    }
    if (!json[key].is_array() || json[key].size() != N) {
        throw common::InputError(path,
                                 std::string(key) + ": expected " + std::to_string(N) + " numbers");
    }
    for (std::size_t i = 0; i < N; ++i) {
        if (json[key][i].is_number()) {
            values[i] = json[key][i].get<double>();
        } else if (!json[key][i].is_null()) {
            throw common::InputError(path, std::string(key) + ": expected numbers or null");
        }
    }
    return values;
}

// A plot of the three response curves (and the identity, grey) on a square tile.
image::SheetTile responseTile(const ProjectorRadiometry& r) {
    constexpr int kSize = 256;
    image::SheetTile tile{"response above black (r, g, b)", kSize, kSize, 3,
                          std::vector<float>(kSize * kSize * 3, 0.08f)};
    const auto plot = [&](double x, double y, std::array<float, 3> colour) {
        const int px = std::clamp(static_cast<int>(std::lround(x * (kSize - 1))), 0, kSize - 1);
        const int py =
            std::clamp(static_cast<int>(std::lround((1 - y) * (kSize - 1))), 0, kSize - 1);
        std::copy(colour.begin(), colour.end(),
                  tile.pixels.begin() + 3 * (static_cast<std::ptrdiff_t>(py) * kSize + px));
    };
    for (int i = 0; i < 4 * kSize; ++i) {
        const double t = i / (4.0 * kSize - 1);
        plot(t, t, {0.35f, 0.35f, 0.35f});
        for (std::size_t c = 0; c < 3; ++c) {
            // Linear between the measured levels, as the device interpolates.
            std::size_t l = 1;
            while (l + 1 < r.levels.size() && r.levels[l] < t) {
                ++l;
            }
            const double t0 = r.levels[l - 1], t1 = r.levels[l];
            const double g = r.response[c][l - 1] +
                             (t - t0) / (t1 - t0) * (r.response[c][l] - r.response[c][l - 1]);
            std::array<float, 3> colour{0.2f, 0.2f, 0.2f};
            colour[c] = 1.0f;
            plot(t, g, colour);
        }
    }
    return tile;
}

// An RGB map shown for the eye: divided by a high quantile of its luminance, then sRGB.
image::SheetTile rgbTile(std::string label, int width, int height,
                         const std::vector<float>& values) {
    std::vector<double> luminance;
    for (std::size_t p = 0; 3 * p < values.size(); ++p) {
        if (!std::isnan(values[3 * p])) {
            luminance.push_back(double(values[3 * p] + values[3 * p + 1] + values[3 * p + 2]) / 3);
        }
    }
    const double scale =
        luminance.empty() ? 1.0 : 1.0 / std::max(1e-12, common::quantile(luminance, 0.99));
    image::SheetTile tile{std::move(label), width, height, 3,
                          std::vector<float>(values.size(), 0.0f)};
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double v =
            std::isnan(values[i]) ? 0.0 : std::clamp(double(values[i]) * scale, 0.0, 1.0);
        tile.pixels[i] = static_cast<float>(proto::linearToSrgb(v));
    }
    return tile;
}

}  // namespace

void writeRadiometry(const ProjectorRadiometry& r, const std::filesystem::path& folder) {
    image::writeImage(folder / kIrradianceFile, r.width, r.height, 3, r.irradiance,
                      image::PixelFormat::kFloat);
    image::writeImage(folder / kFloorFile, r.width, r.height, 3, r.floor,
                      image::PixelFormat::kFloat);
    std::ostringstream csv;
    csv << "# the projector's response above its black level, per channel, measured by vpe "
           "radiometry\nlevel,r,g,b\n";
    char line[128];
    for (std::size_t l = 0; l < r.levels.size(); ++l) {
        std::snprintf(line, sizeof line, "%.6f,%.7f,%.7f,%.7f\n", r.levels[l], r.response[0][l],
                      r.response[1][l], r.response[2][l]);
        csv << line;
    }
    proto::writeTextFileAtomically(folder / kResponseFile, csv.str());
    nlohmann::json json;
    json["format"] = "vpe-measured-radiometry";
    json["version"] = 1;
    json["projector"] = {r.width, r.height};
    json["mixing"] = arrayJson(r.mixing);
    json["mixing_spread"] = arrayJson(r.mixingSpread);
    json["mixing_noise"] = arrayJson(r.mixingNoise);
    // The floor's split (floor_split.h); null where the object cannot tell it.
    const FloorSplit& split = r.floorSplit;
    json["floor"] = arrayJson(split.floor);
    json["floor_separable"] = split.separable;
    json["camera_black_given"] = split.cameraBlackGiven;
    json["camera_black"] = arrayJson(split.cameraBlack);
    json["camera_black_sigma"] = arrayJson(split.cameraBlackSigma);
    json["projector_black"] = arrayJson(split.projectorBlack);
    json["projector_black_sigma"] = arrayJson(split.projectorBlackSigma);
    json["ambient"] = arrayJson(split.ambient);
    json["ambient_sigma"] = arrayJson(split.ambientSigma);
    json["ambient_at_most"] = arrayJson(split.ambientAtMost);
    json["ambient_leverage"] = arrayJson(split.ambientLeverage);
    json["measured_pixels"] = r.measured;
    json["white_saturated_share"] = r.whiteSaturatedShare;
    json["white_signal"] = r.whiteSignal;
    json["camera_linear"] = r.cameraLinear;
    json["exposure_us"] = r.exposureUs;
    proto::writeTextFileAtomically(folder / kMeasuredFile, json.dump(2) + "\n");
}

ProjectorRadiometry readRadiometry(const std::filesystem::path& folder) {
    ProjectorRadiometry r;
    const std::filesystem::path measured = folder / kMeasuredFile;
    std::ifstream stream(measured);
    if (!stream) {
        throw common::InputError(measured, "cannot open (a folder vpe radiometry wrote?)");
    }
    nlohmann::json json;
    try {
        json = nlohmann::json::parse(stream);
    } catch (const nlohmann::json::exception&) {
        throw common::InputError(measured, "not JSON");
    }
    if (json.value("format", "") != "vpe-measured-radiometry" || json.value("version", 0) != 1) {
        throw common::InputError(measured, "format: expected vpe-measured-radiometry version 1");
    }
    r.mixing = arrayOf<9>(json, measured, "mixing");
    r.mixingSpread = arrayOf<9>(json, measured, "mixing_spread");
    r.mixingNoise = arrayOf<9>(json, measured, "mixing_noise");
    // The split as written (an older file has the projector's black as black_level, and
    // no errors).
    FloorSplit& split = r.floorSplit;
    split.floor = measuredArrayOf<3>(json, measured, "floor");
    split.separable = json.value("floor_separable", true);
    split.cameraBlackGiven = json.value("camera_black_given", false);
    split.cameraBlack = measuredArrayOf<3>(json, measured, "camera_black");
    split.cameraBlackSigma = measuredArrayOf<3>(json, measured, "camera_black_sigma");
    split.projectorBlack = measuredArrayOf<3>(
        json, measured, json.contains("projector_black") ? "projector_black" : "black_level");
    split.projectorBlackSigma = measuredArrayOf<3>(json, measured, "projector_black_sigma");
    split.ambient = measuredArrayOf<3>(json, measured, "ambient");
    split.ambientSigma = measuredArrayOf<3>(json, measured, "ambient_sigma");
    split.ambientAtMost = measuredArrayOf<3>(json, measured, "ambient_at_most");
    split.ambientLeverage = measuredArrayOf<3>(json, measured, "ambient_leverage");
    for (std::size_t k = 0; k < 3; ++k) {
        if (!(std::abs(r.mixing[4 * k] - 1) < 1e-9)) {
            throw common::InputError(measured, "mixing: its diagonal must be 1");
        }
    }
    for (const double v : r.mixing) {
        if (!std::isfinite(v) || v < 0) {
            throw common::InputError(measured, "mixing: expected finite numbers ≥ 0");
        }
    }
    const image::FloatImage irradiance =
        image::readImageChannels(folder / kIrradianceFile, {"R", "G", "B"});
    const image::FloatImage floor = image::readImageChannels(folder / kFloorFile, {"R", "G", "B"});
    if (floor.width != irradiance.width || floor.height != irradiance.height) {
        throw common::InputError(folder / kFloorFile,
                                 "not the size of " + std::string(kIrradianceFile));
    }
    r.width = irradiance.width;
    r.height = irradiance.height;
    r.irradiance = irradiance.pixels;
    r.floor = floor.pixels;
    for (std::size_t p = 0; 3 * p < r.irradiance.size(); ++p) {
        r.measured += std::isnan(r.irradiance[3 * p]) ? 0 : 1;
    }
    // The samples as written; vpe bake reads the file itself through readProjectorResponseCsv,
    // which refuses a malformed one.
    std::ifstream csv(folder / kResponseFile);
    std::string line;
    while (std::getline(csv, line)) {
        double level = 0, g[3] = {0, 0, 0};
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &level, &g[0], &g[1], &g[2]) == 4) {
            r.levels.push_back(level);
            for (std::size_t c = 0; c < 3; ++c) {
                r.response[c].push_back(g[c]);
            }
        }
    }
    return r;
}

void writeRadiometrySheet(const ProjectorRadiometry& r, const scan::ProjectorSurface& surface,
                          const proto::PinholeCamera& projector,
                          const std::filesystem::path& path) {
    std::vector<float> albedo(r.irradiance.size(), std::nanf(""));
    for (std::size_t p = 0; 3 * p < r.irradiance.size(); ++p) {
        const double geometry =
            projectorGeometry(projector, &surface.position[3 * p], &surface.normal[3 * p]);
        if (geometry > 0 && !std::isnan(r.irradiance[3 * p])) {
            for (std::size_t c = 0; c < 3; ++c) {
                albedo[3 * p + c] = static_cast<float>(double(r.irradiance[3 * p + c]) / geometry);
            }
        }
    }
    std::vector<image::SheetTile> tiles;
    tiles.push_back(
        rgbTile("irradiance factor F (albedo x geometry)", r.width, r.height, r.irradiance));
    tiles.push_back(rgbTile("albedo: F / (cos / d^2)", r.width, r.height, albedo));
    tiles.push_back(rgbTile("floor D (room light + projector black)", r.width, r.height, r.floor));
    tiles.push_back(responseTile(r));
    image::writeContactSheet(path, tiles, 2);
}

}  // namespace vpe::radiometry
