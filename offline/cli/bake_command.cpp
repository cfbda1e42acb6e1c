// SPDX-License-Identifier: MIT
// vpe bake (--texture MODEL.exr | --quilt DIR --preset NAME=WEIGHTS...) [--mesh FILE]
//          [--projector FILE] [--theta-basis K|full] ... --out scene.vpeb
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <set>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "vpe/bake/scene_baker.h"
#include "vpe/common/atomic_folder.h"
#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/atomic_file.h"
#include "vpe/proto/viewing_zone.h"
#include "vpe/scene/projector_calibration.h"
#include "vpe/scene/scene_settings.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

// `count` eyes evenly around the object frame's vertical (y) axis, at the viewer's height and
// distance from the axis, the first at the viewer (docs/visitors.md).
std::vector<std::array<float, 3>> viewingRing(int count, const proto::Vec3<double>& viewer) {
    if (count < 0 || count > proto::kMaxViewingZone) {
        throw common::InputError("--viewing-zone: " + std::to_string(count) +
                                 " eyes, expected 0 to " + std::to_string(proto::kMaxViewingZone));
    }
    const double radius = std::hypot(viewer.x, viewer.z);
    if (count > 0 && !(radius > 0)) {
        throw common::InputError(
            "--viewing-zone: --viewer stands on the object's vertical axis, "
            "so the ring around it has no radius");
    }
    const double start = std::atan2(viewer.x, viewer.z);
    std::vector<std::array<float, 3>> eyes;
    for (int k = 0; k < count; ++k) {
        const double azimuth = start + 2 * std::numbers::pi * k / count;
        eyes.push_back({static_cast<float>(radius * std::sin(azimuth)),
                        static_cast<float>(viewer.y),
                        static_cast<float>(radius * std::cos(azimuth))});
    }
    return eyes;
}

std::array<float, 3> toFloats(const std::array<double, 3>& values) {
    return {static_cast<float>(values[0]), static_cast<float>(values[1]),
            static_cast<float>(values[2])};
}

// --theta-basis: a number of functions, or full (0 too): none stored, rendered exactly.
int parseThetaBasis(const std::string& text) {
    if (text == "full") {
        return 0;
    }
    int size = -1;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), size);
    if (error != std::errc() || end != text.data() + text.size() || size < 0) {
        throw common::InputError("--theta-basis '" + text +
                                 "': expected a number of functions or full");
    }
    return size;
}

std::string thetaBasisText(const bake::BakeReport& report) {
    if (report.thetaBasis == 0) {
        return "no θs basis";
    }
    char text[64];
    std::snprintf(text, sizeof text, "θs basis %d, %.4f%% kept", report.thetaBasis,
                  100.0 * report.thetaEnergyKept);
    return text;
}

}  // namespace

namespace {

struct BakeArguments {
    bake::BakeOptions options;
    std::string texture, quilt, mesh, projectorSize, calibrationUnit, out;
    std::vector<std::string> projectors, scans, radiometry;
    std::vector<std::string> presets;
    double blendFeather = 0;
    std::string viewer = "0,0.075,1", albedo = "0.85", ambient = "0,0,0";
    std::string encoding = "low-rank";
    std::string relief = "on";
    std::string thetaBasis;
    int threads = 0;
    int viewingZone = 0;  // eyes in a ring at the viewer's height and distance; 0: the viewer alone
    bool json = false;
};

void runShow(const BakeArguments& args, const bake::BakeOptions& options);

// What `vpe bake` does once its options are parsed.
void runBake(const BakeArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    bake::BakeOptions options = args.options;
    options.texture = args.texture;
    options.quilt = args.quilt;
    options.mesh = args.mesh;
    if (!args.projectorSize.empty()) {
        const SizeArgument size = parseSizeArgument(args.projectorSize, "--projector-size", 8192);
        options.projectorWidth = size.width;
        options.projectorHeight = size.height;
    }
    if (!args.calibrationUnit.empty()) {
        options.projectorMetresPerUnit = scene::metresPerLengthUnit(args.calibrationUnit);
    }
    for (const std::string& preset : args.presets) {
        const std::size_t equals = preset.find('=');
        if (equals == std::string::npos || equals == 0 || equals + 1 == preset.size()) {
            throw common::InputError("--preset '" + preset + "': expected NAME=WEIGHTS");
        }
        options.presets.push_back({preset.substr(0, equals), preset.substr(equals + 1)});
    }
    const auto viewer = scene::parsePosition(args.viewer, "--viewer");
    options.settings.viewerPosition = {static_cast<float>(viewer.x), static_cast<float>(viewer.y),
                                       static_cast<float>(viewer.z)};
    options.settings.viewingZone = viewingRing(args.viewingZone, viewer);
    options.settings.screenAlbedo = toFloats(scene::parseAlbedo(args.albedo, "--albedo"));
    options.settings.ambientIrradiance = toFloats(scene::parseAmbient(args.ambient, "--ambient"));
    options.lowRank = args.encoding == "low-rank";
    options.relief = args.relief == "on";
    if (!args.thetaBasis.empty()) {
        options.thetaBasis = parseThetaBasis(args.thetaBasis);
    }
    options.threads = common::resolveThreadCount(args.threads);
    options.registration.threads = options.threads;
    if (args.projectors.size() + args.scans.size() > 1) {
        runShow(args, options);
        return;
    }
    if (args.radiometry.size() > 1) {
        throw common::InputError("--radiometry: " + std::to_string(args.radiometry.size()) +
                                 " given for one projector");
    }
    options.projector = args.projectors.empty() ? "" : args.projectors.front();
    options.scan = args.scans.empty() ? "" : args.scans.front();
    options.radiometry = args.radiometry.empty() ? "" : args.radiometry.front();

    const bake::BakeReport report = bake::bakeScene(options, args.out);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string camera = report.camera ? "camera " + std::to_string(report.cameraWidth) +
                                                   "x" + std::to_string(report.cameraHeight)
                                             : std::string("no camera");
    std::fprintf(stderr,
                 "%s: %d region%s of %dx%d (M = %d, %s, %d bytes/texel%s, %s), mesh %zu "
                 "vertices / %zu triangles, %s, %.1f MiB in %.2f s\n",
                 args.out.c_str(), report.regions, report.regions == 1 ? "" : "s",
                 report.textureWidth, report.textureHeight, report.harmonics, args.encoding.c_str(),
                 report.bytesPerTexel, report.relief ? " + 4 of relief" : "",
                 thetaBasisText(report).c_str(), report.vertices, report.triangles, camera.c_str(),
                 static_cast<double>(report.bytes) / (1024.0 * 1024.0), seconds);
    if (!options.radiometry.empty()) {
        std::fprintf(stderr,
                     "measured light: %zu projector pixels on the mesh, %zu of them (%.2f%%) "
                     "completed from their neighbours where the camera did not see\n",
                     report.radiometryCovered, report.radiometryCompleted,
                     report.radiometryCovered ? 100.0 * double(report.radiometryCompleted) /
                                                    double(report.radiometryCovered)
                                              : 0.0);
    }
    std::fprintf(stderr, "sampling %s in u%s\n", report.wrapU ? "wraps" : "clamps",
                 report.meshWrapsU && !report.wrapU
                     ? ": the mesh's u wraps but the textures do not tile, so u = 0 | 1 "
                       "shows as a seam (vpe quilt --wrap auto makes them tile)"
                     : "");
    const std::optional<bake::ScanPlacement>& placement = report.placement;
    if (placement && placement->registration) {
        const registration::RegistrationResult& r = *placement->registration;
        std::fprintf(
            stderr,
            "registered %s to the scan: residual %.3f mm over %.1f%% of %zu scan points%s\n",
            args.mesh.c_str(), r.rmsMm, 100 * r.inlierShare, r.scanPoints,
            r.turnUnmeasured
                ? ("; a surface of revolution: its turn about the axis is not measured, "
                   "so its front (+z) was turned " +
                   std::to_string(static_cast<int>(std::lround(r.turnSetDeg))) +
                   "° to face the projector")
                      .c_str()
                : "");
    } else if (placement) {
        std::fprintf(stderr, "the scan's own surface is the screen object (%s chart)\n",
                     registration::surfaceChartName(*placement->chart));
    }
    if (args.json) {
        nlohmann::json json;
        json["out"] = args.out;
        if (placement) {
            json["object_to_camera"] = {{"R", placement->objectToCamera.R},
                                        {"t", placement->objectToCamera.t}};
            if (placement->registration) {
                const registration::RegistrationResult& r = *placement->registration;
                json["registration"] = {{"rms_mm", r.rmsMm},
                                        {"inlier_share", r.inlierShare},
                                        {"scan_points", r.scanPoints},
                                        {"turn_unmeasured", r.turnUnmeasured},
                                        {"turn_set_deg", r.turnSetDeg},
                                        {"axis", r.axis},
                                        {"axis_point", r.axisPoint}};
            } else {
                json["surface_chart"] = registration::surfaceChartName(*placement->chart);
            }
        }
        json["regions"] = report.regions;
        json["texture_width"] = report.textureWidth;
        json["texture_height"] = report.textureHeight;
        json["harmonics"] = report.harmonics;
        json["encoding"] = args.encoding;
        json["bytes_per_texel"] = report.bytesPerTexel;
        json["relief"] = report.relief;
        json["explained_variance"] = report.explainedVariance;
        json["coefficient_rms"] = report.coefficientRms;
        json["theta_basis"] =
            report.thetaBasis > 0 ? nlohmann::json(report.thetaBasis) : nlohmann::json("full");
        json["theta_energy_kept"] = report.thetaEnergyKept;
        json["vertices"] = report.vertices;
        json["triangles"] = report.triangles;
        json["wrap_u"] = report.wrapU;
        json["mesh_wraps_u"] = report.meshWrapsU;
        json["camera"] = report.camera;
        if (!options.radiometry.empty()) {
            json["radiometry"] = {{"covered_pixels", report.radiometryCovered},
                                  {"completed_pixels", report.radiometryCompleted}};
        }
        json["bytes"] = report.bytes;
        json["checksum"] = report.checksum;
        json["seconds"] = seconds;
        printJson(json.dump());
    }
}

// The names of a show's bundles: the calibration files' or scans' names, or projector1… when
// two would clash.
std::vector<std::string> showNames(const std::vector<std::filesystem::path>& sources) {
    std::vector<std::string> names;
    std::set<std::string> seen;
    bool clash = false;
    for (const std::filesystem::path& source : sources) {
        std::filesystem::path path = source;
        if (!path.has_filename()) {
            path = path.parent_path();
        }
        names.push_back(path.stem().string());
        clash = clash || names.back().empty() || !seen.insert(names.back()).second;
    }
    if (clash) {
        for (std::size_t i = 0; i < names.size(); ++i) {
            names[i] = "projector" + std::to_string(i + 1);
        }
    }
    return names;
}

// The surface's reach in texture space: red where no projector reaches, then grey, blue and
// green for one, two, three or more; black off the surface.
std::vector<std::uint8_t> reachPicture(const renderer::ScalarImage<std::uint8_t>& reach) {
    static constexpr std::uint8_t kColours[5][3] = {
        {230, 40, 40}, {120, 120, 120}, {70, 130, 210}, {60, 190, 110}, {0, 0, 0}};
    std::vector<std::uint8_t> out(3 * reach.values.size());
    for (std::size_t i = 0; i < reach.values.size(); ++i) {
        const std::uint8_t count = reach.values[i];
        const auto* colour = kColours[count == 255 ? 4 : std::min<int>(count, 3)];
        std::copy(colour, colour + 3, &out[3 * i]);
    }
    return out;
}

// A share map as grey levels (s · 255), the projector's size.
std::vector<std::uint8_t> sharePicture(const renderer::FloatImage& share) {
    std::vector<std::uint8_t> out(share.values.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = static_cast<std::uint8_t>(
            std::lround(255.0 * std::clamp(static_cast<double>(share.values[i]), 0.0, 1.0)));
    }
    return out;
}

// `vpe bake` with several projectors: one bundle each in the folder --out, with the share maps
// and the surface's reach as pictures and show.json.
void runShow(const BakeArguments& args, const bake::BakeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    if (!args.projectors.empty() && !args.scans.empty()) {
        throw common::InputError(
            "bake: a show's projectors are all --projector files or all --scan "
            "folders");
    }
    const bool scans = !args.scans.empty();
    const std::vector<std::string>& sources = scans ? args.scans : args.projectors;
    if (!args.radiometry.empty() && args.radiometry.size() != sources.size()) {
        throw common::InputError("--radiometry: " + std::to_string(args.radiometry.size()) +
                                 " given for " + std::to_string(sources.size()) +
                                 " projectors (one each, or none)");
    }
    const std::vector<std::string> names = showNames({sources.begin(), sources.end()});
    common::AtomicFolder folder(args.out, "show.json", "vpe bake");
    std::vector<bake::ShowProjector> projectors;
    for (std::size_t i = 0; i < sources.size(); ++i) {
        bake::ShowProjector projector;
        (scans ? projector.scan : projector.calibration) = sources[i];
        if (!args.radiometry.empty()) {
            projector.radiometry = args.radiometry[i];
        }
        projector.out = folder.temporaryPath() / (names[i] + ".vpeb");
        projectors.push_back(std::move(projector));
    }
    bake::BlendOptions blend;
    blend.featherPixels = args.blendFeather;
    blend.threads = static_cast<int>(options.threads);
    if (!(args.blendFeather >= 0) || !std::isfinite(args.blendFeather)) {
        throw common::InputError("--blend-feather: expected pixels ≥ 0");
    }
    const bake::ShowReport show = bake::bakeShow(options, projectors, blend);
    nlohmann::json json;
    json["out"] = args.out;
    json["projectors"] = nlohmann::json::array();
    for (std::size_t i = 0; i < projectors.size(); ++i) {
        const renderer::FloatImage& share = show.blend.shares[i];
        image::writeImage8(folder.temporaryPath() / (names[i] + "-share.png"), share.width,
                           share.height, 1, sharePicture(share));
        std::size_t lit = 0, shared = 0;
        for (const float s : share.values) {
            lit += s > 0 ? 1 : 0;
            shared += s > 0 && s < 0.999f ? 1 : 0;
        }
        json["projectors"].push_back({{"name", names[i]},
                                      {"source", sources[i]},
                                      {"bundle", names[i] + ".vpeb"},
                                      {"lit_pixels", lit},
                                      {"blended_pixels", shared},
                                      {"bytes", show.bundles[i].bytes},
                                      {"checksum", show.bundles[i].checksum}});
    }
    image::writeImage8(folder.temporaryPath() / "reach.png", show.blend.reach.width,
                       show.blend.reach.height, 3, reachPicture(show.blend.reach));
    json["unreached_share"] = show.blend.unreachedShare;
    json["overlap_share"] = show.blend.overlapShare;
    json["seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    proto::writeTextFileAtomically(folder.temporaryPath() / "show.json", json.dump(2) + "\n");
    folder.commit();
    std::fprintf(stderr,
                 "%s: %zu projectors, one bundle each; %.2f%% of the surface reached by none "
                 "(reach.png), %.1f%% by two or more, blended; %.1f s\n",
                 args.out.c_str(), projectors.size(), 100 * show.blend.unreachedShare,
                 100 * show.blend.overlapShare, json["seconds"].get<double>());
    if (args.json) {
        printJson(json.dump());
    }
}

}  // namespace

void addBakeCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<BakeArguments>();
    CLI::App* command = app.add_subcommand(
        "bake", "Combine texture, screen mesh and projector calibration into a device bundle");
    command->add_option("--texture", args->texture, "One composed texture (model file, .exr)");
    command->add_option("--quilt", args->quilt,
                        "Or the region maps of vpe quilt, blended on the device by presets");
    command->add_option("--preset", args->presets,
                        "NAME=WEIGHTS: a weight-map preset for --quilt (vpe compose's --weights "
                        "spec); repeat for more; the first is the default");
    command->add_option("--mesh", args->mesh,
                        "Screen object (OBJ or PLY with UVs); default: the built-in vase, or with "
                        "--scan the scan's own surface");
    command->add_option("--scan", args->scans,
                        "A scan (vpe scan's --out): its calibration, and the mesh registered to "
                        "it (or its surface when no --mesh); repeat for a show of several "
                        "projectors seen by one camera (the first scan places the object)");
    addMeshScaleOption(command, args->options.meshMetresPerUnit);
    command->add_option("--projector", args->projectors,
                        "Projector calibration (OpenCV YAML/XML: proj_K, proj_kc, R, T; with "
                        "cam_K, cam_kc, cam_width, cam_height the bundle carries the camera "
                        "too; or procam-calibration's calibration_result.xml); default: a demo "
                        "projector facing the object. Repeat for a show "
                        "of several projectors on one object: --out is then a folder with one "
                        "bundle per projector, each with its share of the light");
    command->add_option("--projector-size", args->projectorSize,
                        "Projector resolution WxH, when the calibration file has none");
    addCalibrationUnitOption(command, args->calibrationUnit);
    command
        ->add_option("--demo-distance", args->options.demoDistance,
                     "Distance of the demo projector from the object (m)")
        ->capture_default_str();
    command
        ->add_option("--viewing-zone", args->viewingZone,
                     "Visitors around the object at once: N eyes in a ring around the object "
                     "frame's vertical axis at --viewer's height and distance, the first at "
                     "--viewer; each point is drawn for the mean direction to those that see it "
                     "(docs/visitors.md). 0: --viewer alone")
        ->capture_default_str();
    command->add_option("--viewer", args->viewer, "Viewer position x,y,z (m, object frame)")
        ->capture_default_str();
    command->add_option("--albedo", args->albedo, "Screen albedo: one value or r,g,b")
        ->capture_default_str();
    command->add_option("--ambient", args->ambient, "Ambient irradiance r,g,b (linear)")
        ->capture_default_str();
    command
        ->add_option("--response", args->options.response,
                     "Projector response: a gamma, r,g,b gammas, or a CSV curve "
                     "(level,r,g,b)")
        ->capture_default_str();
    command->add_option("--radiometry", args->radiometry,
                        "The light measured on site (vpe radiometry's --out): the bundle "
                        "compensates with its maps, crosstalk and response instead of "
                        "--albedo, --ambient and --response; in a show, one per projector, "
                        "in their order");
    command
        ->add_option("--blend-feather", args->blendFeather,
                     "A show's fade at the edge of each projector's reach, in its pixels "
                     "(0: 8% of its shorter side)")
        ->capture_default_str();
    command
        ->add_option("--peak-irradiance", args->options.settings.peakIrradiance,
                     "Projector irradiance at 1 m, normal incidence, full level")
        ->capture_default_str();
    command
        ->add_option("--gain", args->options.settings.gain, "Global gain on the rendered radiance")
        ->capture_default_str();
    command
        ->add_option("--encoding", args->encoding,
                     "Texture encoding: low-rank (PCA basis, half-float weights) or full")
        ->check(CLI::IsMember({"low-rank", "full"}))
        ->capture_default_str();
    command->add_option("--rank", args->options.rank, "Low-rank: basis vectors per region")
        ->capture_default_str();
    command
        ->add_option("--relief", args->relief,
                     "on: carry the textures' relief (detail normal maps, when they have one) "
                     "into the bundle; off: leave it out, the mesh's normals alone")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    command->add_option("--theta-basis", args->thetaBasis,
                        "θs functions the device renders in, fitted to the textures "
                        "(proto/MODEL.md); full or 0: none, rendered exactly [default: 4]");
    addThreadsOption(command, args->threads);
    command
        ->add_option("--out", args->out,
                     "Bundle to write (.vpeb); with several projectors, the show's folder")
        ->required();
    addJsonFlag(command, args->json);
    command->callback([args, &action] { action = [args] { runBake(*args); }; });
}

}  // namespace vpe::cli
