// SPDX-License-Identifier: MIT
// vpe info BUNDLE [--json]: what a device bundle holds, read through the device's own reader
// (so a bundle `vpe info` accepts is one the device accepts, checksum included).
#include <array>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/half_float.h"

#include "cli/commands.h"

namespace vpe::cli {

namespace {

using proto::AlphaEncoding;
using proto::CoefficientEncoding;
using proto::CoefficientMapView;

const char* encodingName(CoefficientEncoding encoding) {
    return encoding == CoefficientEncoding::kFull ? "full" : "low_rank";
}

const char* alphaName(AlphaEncoding encoding) {
    return encoding == AlphaEncoding::kUnorm8 ? "unorm8" : "float16";
}

std::string hex32(std::uint32_t value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", static_cast<unsigned>(value));
    return text;
}

// A float as the shortest decimal that reads back as it (0.85f prints as 0.85, not
// 0.8500000238418579).
double decimal(float value) {
    char text[32];
    const auto [end, error] = std::to_chars(text, text + sizeof text, value);
    return error == std::errc() ? std::strtod(std::string(text, end).c_str(), nullptr)
                                : static_cast<double>(value);
}

nlohmann::json decimals(const std::array<float, 3>& values) {
    return {decimal(values[0]), decimal(values[1]), decimal(values[2])};
}

nlohmann::json mapJson(const CoefficientMapView& map) {
    nlohmann::json json{{"encoding", encodingName(map.encoding)},
                        {"layers", map.layers.layers},
                        {"bytes_per_texel", map.bytesPerTexel()},
                        {"bytes", map.layers.bytes()}};
    if (map.encoding == CoefficientEncoding::kLowRank) {
        json["rank"] = map.rank;
    }
    json["relief"] = !map.detailNormals.empty();  // format 1.2's detail normal map
    return json;
}

nlohmann::json responseJson(const proto::ResponseCurves& response) {
    if (response.kind == proto::ResponseKind::kGamma) {
        return {{"kind", "gamma"}, {"gamma", decimals(response.gamma)}};
    }
    return {{"kind", "curve"},
            {"samples",
             {response.curve[0].size(), response.curve[1].size(), response.curve[2].size()}}};
}

// K, or "full" for a bundle without a θs basis (as vpe bake --json reports it).
nlohmann::json thetaBasisJson(const proto::BundleModel& model) {
    return model.thetaBasis.empty() ? nlohmann::json("full")
                                    : nlohmann::json(model.thetaBasisSize());
}

std::string thetaBasisText(const proto::BundleModel& model) {
    if (model.thetaBasis.empty()) {
        return "theta basis: none: rendered exactly";
    }
    const int size = model.thetaBasisSize();
    return "theta basis: " + std::to_string(size) + (size == 1 ? " function" : " functions") +
           " (orthonormal over [0, π])";
}

nlohmann::json pinholeJson(const proto::ProjectorCalibration& p) {
    return {{"width", p.width},           {"height", p.height},     {"intrinsics", p.intrinsics},
            {"distortion", p.distortion}, {"rotation", p.rotation}, {"translation", p.translation}};
}

nlohmann::json infoJson(const std::string& path, const proto::BundleView& bundle) {
    const proto::BundleHeader& header = bundle.header();
    const proto::ProjectorCalibration& projector = bundle.projector();
    const proto::RenderSettings& settings = bundle.settings();
    nlohmann::json json;
    json["file"] = path;
    json["format_version"] =
        std::to_string(header.majorVersion) + "." + std::to_string(header.minorVersion);
    json["file_bytes"] = header.fileSize;
    json["metadata_bytes"] = header.metadataSize;
    json["checksum"] = hex32(header.checksum);
    json["checksum_ok"] = bundle.checksumVerified();
    json["mesh"] = {{"vertices", bundle.mesh().vertexCount()},
                    {"triangles", bundle.mesh().triangleCount()}};
    json["projector"] = pinholeJson(projector);
    // Format 1.3: the installation's camera; null when the bundle carries none.
    json["camera"] = bundle.camera() ? pinholeJson(*bundle.camera()) : nlohmann::json(nullptr);
    // Format 1.4: the measured light's crosstalk; null when the bundle assumes its light.
    json["radiometry"] = bundle.radiometry()
                             ? nlohmann::json{{"mixing", bundle.radiometry()->mixing}}
                             : nlohmann::json(nullptr);
    // Format 1.5: the projector's part in a show of several; null when it is the only one.
    json["blend"] = bundle.blend() ? nlohmann::json{{"projectors", bundle.blend()->projectors},
                                                    {"index", bundle.blend()->index}}
                                   : nlohmann::json(nullptr);
    json["settings"] = {{"viewer_position", decimals(settings.viewerPosition)},
                        {"screen_albedo", decimals(settings.screenAlbedo)},
                        {"ambient_irradiance", decimals(settings.ambientIrradiance)},
                        {"response", responseJson(settings.response)},
                        {"peak_irradiance", decimal(settings.peakIrradiance)},
                        {"gain", decimal(settings.gain)}};
    json["model"] = {{"harmonics", bundle.model().harmonics},
                     {"lambda", bundle.model().lambda},
                     {"layout", proto::kBundleCoefficientLayout},
                     {"coefficients_per_texel", bundle.model().coefficientsPerTexel()},
                     {"theta_basis", thetaBasisJson(bundle.model())}};
    nlohmann::json regions = nlohmann::json::array();
    for (const proto::RegionView& region : bundle.regions()) {
        nlohmann::json entry = mapJson(region.coefficients);
        entry["name"] = std::string(region.name);
        regions.push_back(entry);
    }
    json["textures"] = {
        {"width", bundle.textureWidth()},
        {"height", bundle.textureHeight()},
        {"wrap_u", bundle.textureWrapsU()},
        {"regions", regions},
        {"composed", bundle.composed() ? mapJson(*bundle.composed()) : nlohmann::json(nullptr)}};
    nlohmann::json presets = nlohmann::json::array();
    for (const proto::WeightPresetView& preset : bundle.presets()) {
        presets.push_back({{"name", std::string(preset.name)},
                           {"encoding", alphaName(preset.encoding)},
                           {"bytes_per_texel", preset.bytesPerTexel()}});
    }
    json["presets"] = presets;
    return json;
}

std::string triple(const auto& values) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", static_cast<double>(values[0]),
                  static_cast<double>(values[1]), static_cast<double>(values[2]));
    return text;
}

std::string mapText(const CoefficientMapView& map) {
    std::string text = encodingName(map.encoding);
    if (map.encoding == CoefficientEncoding::kLowRank) {
        text += ", rank " + std::to_string(map.rank);
    }
    return text + ", " + std::to_string(map.layers.layers) + " RGBA16F layers, " +
           std::to_string(map.bytesPerTexel()) + " bytes per texel" +
           (map.detailNormals.empty() ? "" : ", relief (4 bytes per texel)");
}

// Two lines: resolution, intrinsics and distortion; the pose.
void printPinhole(const char* what, const proto::ProjectorCalibration& p) {
    std::printf(
        "%-10s %u x %u, fx %.6g fy %.6g cx %.6g cy %.6g, distortion %.4g %.4g %.4g %.4g %.4g\n",
        what, p.width, p.height, p.intrinsics[0], p.intrinsics[4], p.intrinsics[2], p.intrinsics[5],
        p.distortion[0], p.distortion[1], p.distortion[2], p.distortion[3], p.distortion[4]);
    std::printf("           R rows %s %s %s, T %s m\n", triple(&p.rotation[0]).c_str(),
                triple(&p.rotation[3]).c_str(), triple(&p.rotation[6]).c_str(),
                triple(p.translation).c_str());
}

void printInfo(const std::string& path, const proto::BundleView& bundle) {
    const proto::BundleHeader& header = bundle.header();
    const proto::ProjectorCalibration& p = bundle.projector();
    const proto::RenderSettings& s = bundle.settings();
    std::printf("%s: vpe bundle %u.%u, %llu bytes (metadata %llu), checksum %s %s\n", path.c_str(),
                static_cast<unsigned>(header.majorVersion),
                static_cast<unsigned>(header.minorVersion),
                static_cast<unsigned long long>(header.fileSize),
                static_cast<unsigned long long>(header.metadataSize),
                hex32(header.checksum).c_str(), bundle.checksumVerified() ? "OK" : "not checked");
    std::printf("mesh       %zu vertices, %zu triangles\n", bundle.mesh().vertexCount(),
                bundle.mesh().triangleCount());
    printPinhole("projector", p);
    if (bundle.camera()) {
        printPinhole("camera", *bundle.camera());
    } else {
        std::printf("camera     none\n");
    }
    std::printf("viewer     %s m\n", triple(s.viewerPosition).c_str());
    if (const auto& blend = bundle.blend()) {
        // Format 1.5: this projector's share of the light among several.
        std::size_t lit = 0, shared = 0;
        for (const std::uint16_t half : blend->share) {
            const float share = proto::halfToFloat(half);
            lit += share > 0 ? 1 : 0;
            shared += share > 0 && share < 0.999f ? 1 : 0;
        }
        std::printf(
            "blend      projector %d of %d: lights %zu pixels, shares %zu of them "
            "(Float16 share map, 2 bytes)\n",
            blend->index + 1, blend->projectors, lit, shared);
    }
    if (const auto& r = bundle.radiometry()) {
        // Format 1.4: the light measured on site replaces the assumed albedo and ambient.
        const auto& x = r->mixing;
        std::printf(
            "radiometry measured per projector pixel (F, D: RGBA16F, 16 bytes); "
            "crosstalk R %.3f %.3f %.3f | G %.3f %.3f %.3f | B %.3f %.3f %.3f; the "
            "response is above black\n",
            x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8]);
    } else {
        std::printf("screen     albedo %s, ambient %s\n", triple(s.screenAlbedo).c_str(),
                    triple(s.ambientIrradiance).c_str());
    }
    if (s.response.kind == proto::ResponseKind::kGamma) {
        std::printf("response   gamma %s", triple(s.response.gamma).c_str());
    } else {
        std::printf("response   curve, %zu/%zu/%zu samples", s.response.curve[0].size(),
                    s.response.curve[1].size(), s.response.curve[2].size());
    }
    std::printf(", peak irradiance %.6g, gain %.6g\n", static_cast<double>(s.peakIrradiance),
                static_cast<double>(s.gain));
    std::printf("model      M = %d, lambda = %.6g, %d values per texel (%s)\n",
                bundle.model().harmonics, bundle.model().lambda,
                bundle.model().coefficientsPerTexel(), proto::kBundleCoefficientLayout);
    std::printf("           %s\n", thetaBasisText(bundle.model()).c_str());
    std::printf("textures   %d x %d, %zu region%s, sampling %s in u\n", bundle.textureWidth(),
                bundle.textureHeight(), bundle.regions().size(),
                bundle.regions().size() == 1 ? "" : "s",
                bundle.textureWrapsU() ? "wraps" : "clamps");
    for (std::size_t r = 0; r < bundle.regions().size(); ++r) {
        const proto::RegionView& region = bundle.regions()[r];
        std::printf("  region %zu '%.*s': %s\n", r, static_cast<int>(region.name.size()),
                    region.name.data(), mapText(region.coefficients).c_str());
    }
    if (bundle.composed()) {
        std::printf("  composed: %s\n", mapText(*bundle.composed()).c_str());
    }
    std::printf("presets    %zu\n", bundle.presets().size());
    for (std::size_t i = 0; i < bundle.presets().size(); ++i) {
        const proto::WeightPresetView& preset = bundle.presets()[i];
        std::printf("  preset %zu '%.*s': %s, %d bytes per texel\n", i,
                    static_cast<int>(preset.name.size()), preset.name.data(),
                    alphaName(preset.encoding), preset.bytesPerTexel());
    }
}

}  // namespace

namespace {

struct InfoArguments {
    std::string bundle;
    bool json = false;
};

// What `vpe info` does once its options are parsed.
void runInfo(const InfoArguments& args) {
    const proto::BundleFile bundle = proto::BundleFile::open(args.bundle);
    if (args.json) {
        printJson(infoJson(args.bundle, bundle.view()).dump());
    } else {
        printInfo(args.bundle, bundle.view());
    }
}

}  // namespace

void addInfoCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<InfoArguments>();
    CLI::App* command = app.add_subcommand(
        "info", "Show what a device bundle holds, after the device's own checks");
    command->add_option("BUNDLE", args->bundle, "Bundle file (.vpeb)")->required();
    command->add_flag("--json", args->json, "Print a JSON report instead of text");
    command->callback([args, &action] { action = [args] { runInfo(*args); }; });
}

}  // namespace vpe::cli
