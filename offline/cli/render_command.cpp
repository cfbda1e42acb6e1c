// SPDX-License-Identifier: MIT
// vpe render scene.vpeb --light x,y,z --out pattern.png [--simulate visitor.png]
//            [--direct direct.png] [--exr pattern.exr] [--weights PRESET] [--gain G|auto]
// The CPU reference renderer: what the projector must show, and, for previews without a
// projector, what a visitor would see and what the material itself would look like.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/common/input_error.h"
#include "vpe/common/parallel_for.h"
#include "vpe/image/image_file.h"
#include "vpe/proto/bundle.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/proto/srgb.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/loop_closure.h"
#include "vpe/renderer/cpu/projector_frame.h"
#include "vpe/renderer/cpu/visitor_view.h"
#include "vpe/scene/scene_settings.h"

#include "cli/commands.h"
#include "cli/common_options.h"
#include "cli/size_argument.h"

namespace vpe::cli {

namespace {

using renderer::Vec3d;

// A picture for people: radiance × exposure, sRGB-encoded.
std::vector<std::uint8_t> srgbPicture(const renderer::RgbImage& radiance, double exposure) {
    std::vector<std::uint8_t> out(radiance.values.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double v = std::clamp(static_cast<double>(radiance.values[i]) * exposure, 0.0, 1.0);
        out[i] = static_cast<std::uint8_t>(std::lround(255.0 * proto::linearToSrgb(v)));
    }
    return out;
}

// What the projector is sent: drive levels, already through the inverse response.
std::vector<std::uint8_t> levelPicture(const renderer::RgbImage& level) {
    std::vector<std::uint8_t> out(level.values.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = static_cast<std::uint8_t>(
            std::lround(255.0 * std::clamp(static_cast<double>(level.values[i]), 0.0, 1.0)));
    }
    return out;
}

// An exposure that puts the 99th percentile of the seen radiance at 0.8.
double autoExposure(const renderer::DirectView& direct) {
    std::vector<float> values;
    for (std::size_t p = 0; p < direct.coverage.values.size(); ++p) {
        if (direct.coverage.values[p]) {
            values.push_back(
                std::max({direct.radiance.values[3 * p], direct.radiance.values[3 * p + 1],
                          direct.radiance.values[3 * p + 2]}));
        }
    }
    if (values.empty()) {
        return 1.0;
    }
    const auto at =
        values.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), at, values.end());
    return *at > 0 ? 0.8 / static_cast<double>(*at) : 1.0;
}

// The middle of the mesh's bounding box: what the preview camera looks at.
proto::Vec3d meshCentre(const proto::MeshView& mesh) {
    float low[3] = {1e30f, 1e30f, 1e30f}, high[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        low[i % 3] = std::min(low[i % 3], mesh.positions[i]);
        high[i % 3] = std::max(high[i % 3], mesh.positions[i]);
    }
    return {0.5 * static_cast<double>(low[0] + high[0]),
            0.5 * static_cast<double>(low[1] + high[1]),
            0.5 * static_cast<double>(low[2] + high[2])};
}

}  // namespace

namespace {

struct RenderArguments {
    std::vector<std::string> bundles;
    std::string bundle, out, simulate, direct, exr, weights, gain;
    std::string light, viewer, viewSize = "480x360";
    double intensity = 1.0, exposure = 0.0, fov = 30.0, clipTarget = 0.005;
    int threads = 0;
    bool json = false;
};

// --gain's number (not 'auto'): positive and finite.
double parseGain(const std::string& text) {
    char* end = nullptr;
    const double gain = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !(gain > 0) || !std::isfinite(gain)) {
        throw common::InputError("--gain: '" + text + "' is not a positive number or 'auto'");
    }
    return gain;
}

// Where the visitor stands: --viewer, or the bundle's viewer.
proto::Vec3d viewerOf(const RenderArguments& args, const renderer::BundleScene& bundleScene) {
    if (args.viewer.empty()) {
        return bundleScene.bundleViewer();
    }
    const auto v = scene::parsePosition(args.viewer, "--viewer");
    return {v.x, v.y, v.z};
}

// The virtual light at --light, of --intensity in every channel.
template <typename Position>
renderer::VirtualLight virtualLightOf(const RenderArguments& args, const Position& light) {
    renderer::VirtualLight virtualLight;
    virtualLight.position = {light.x, light.y, light.z};
    virtualLight.intensity = {args.intensity, args.intensity, args.intensity};
    return virtualLight;
}

// `vpe render` with the bundles of a show (vpe bake with several projectors): a frame per
// projector into the folder --out, and the visitor's view of their combined light.
void runRenderShow(const RenderArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const auto light = scene::parsePosition(args.light, "--light");
    const SizeArgument viewSize = parseSizeArgument(args.viewSize, "--view-size", 8192);
    if (!(args.intensity > 0) || !std::isfinite(args.intensity)) {
        throw common::InputError("--intensity must be a positive number");
    }
    if (!args.exr.empty()) {
        throw common::InputError("--exr: one bundle at a time (a show writes its frames as PNG)");
    }
    std::vector<proto::BundleFile> files;
    std::vector<std::unique_ptr<renderer::BundleScene>> bundleScenes;
    for (const std::string& path : args.bundles) {
        files.push_back(proto::BundleFile::open(path));
    }
    for (std::size_t i = 0; i < files.size(); ++i) {
        try {
            bundleScenes.push_back(
                std::make_unique<renderer::BundleScene>(files[i].view(), args.weights));
        } catch (const std::invalid_argument& error) {
            throw common::InputError(std::string("--weights: ") + error.what());
        }
        if (files[i].view().mesh().positions.size() != files[0].view().mesh().positions.size() ||
            !std::equal(files[i].view().mesh().positions.begin(),
                        files[i].view().mesh().positions.end(),
                        files[0].view().mesh().positions.begin())) {
            throw common::InputError(args.bundles[i] + ": not the same object as " +
                                     args.bundles[0] + " (a show's bundles share one mesh)");
        }
    }
    const proto::Vec3d viewer = viewerOf(args, *bundleScenes[0]);
    const renderer::VirtualLight virtualLight = virtualLightOf(args, light);
    std::vector<renderer::RenderScene> scenes;
    for (const auto& bundleScene : bundleScenes) {
        scenes.push_back(args.viewer.empty() ? bundleScene->scene(virtualLight)
                                             : bundleScene->scene(virtualLight, viewer));
    }
    renderer::RenderOptions options;
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    options.gain = static_cast<double>(files[0].view().settings().gain);
    if (!args.gain.empty() && args.gain != "auto") {
        options.gain = parseGain(args.gain);
    }
    std::vector<renderer::ProjectorFrame> frames;
    for (const renderer::RenderScene& scene : scenes) {
        frames.push_back(renderer::renderProjectorFrame(scene, options));
    }
    if (args.gain == "auto") {  // one gain for all: the lowest any projector needs
        double gain = 1.0;
        for (const renderer::ProjectorFrame& frame : frames) {
            gain = std::min(gain, renderer::gainForClippedFraction(frame, args.clipTarget));
        }
        options.gain = gain;
        for (std::size_t i = 0; i < scenes.size(); ++i) {
            frames[i] = renderer::renderProjectorFrame(scenes[i], options);
        }
    }
    std::filesystem::create_directories(args.out);
    nlohmann::json json;
    json["bundles"] = args.bundles;
    json["gain"] = options.gain;
    json["projectors"] = nlohmann::json::array();
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const std::filesystem::path bundlePath(args.bundles[i]);
        const std::filesystem::path out =
            std::filesystem::path(args.out) / (bundlePath.stem().string() + ".png");
        image::writeImage8(out, frames[i].level.width, frames[i].level.height, 3,
                           levelPicture(frames[i].level));
        json["projectors"].push_back({{"frame", out.string()},
                                      {"covered_pixels", frames[i].stats.coveredPixels},
                                      {"clipped_fraction", frames[i].stats.clippedFraction}});
    }
    if (!args.simulate.empty() || !args.direct.empty()) {
        const proto::PinholeCamera camera = proto::cameraLookingAt(
            viewSize.width, viewSize.height, args.fov, viewer, meshCentre(files[0].view().mesh()));
        const renderer::DirectView direct = renderer::renderDirectView(scenes[0], camera, options);
        std::vector<const renderer::RenderScene*> scenePointers;
        std::vector<const renderer::RgbImage*> patterns;
        for (std::size_t i = 0; i < scenes.size(); ++i) {
            scenePointers.push_back(&scenes[i]);
            patterns.push_back(&frames[i].level);
        }
        const renderer::SimulatedShowView simulated =
            renderer::simulateShowView(scenePointers, patterns, camera, options);
        const double exposure = args.exposure > 0 ? args.exposure : autoExposure(direct);
        if (!args.simulate.empty()) {
            image::writeImage8(args.simulate, viewSize.width, viewSize.height, 3,
                               srgbPicture(simulated.radiance, exposure));
        }
        if (!args.direct.empty()) {
            image::writeImage8(args.direct, viewSize.width, viewSize.height, 3,
                               srgbPicture(direct.radiance, exposure));
        }
        // Against the material rendered directly, over the seen pixels some projector lights:
        // PSNR with the brightest direct radiance as the peak.
        std::size_t seen = 0, lit = 0;
        double peak = 0, squared = 0;
        for (std::size_t p = 0; p < simulated.coverage.values.size(); ++p) {
            if (!simulated.coverage.values[p]) {
                continue;
            }
            ++seen;
            if (simulated.litBy.values[p] == 0) {
                continue;
            }
            ++lit;
            for (std::size_t c = 0; c < 3; ++c) {
                const double d = static_cast<double>(direct.radiance.values[3 * p + c]);
                const double e = static_cast<double>(simulated.radiance.values[3 * p + c]) - d;
                peak = std::max(peak, d);
                squared += e * e;
            }
        }
        const double mse = lit > 0 ? squared / (3.0 * static_cast<double>(lit)) : 0.0;
        json["exposure"] = exposure;
        json["seen_pixels"] = seen;
        json["lit_share"] = seen > 0 ? static_cast<double>(lit) / static_cast<double>(seen) : 0.0;
        json["psnr"] = mse > 0 ? 10 * std::log10(peak * peak / mse) : 999.0;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json["seconds"] = seconds;
    std::fprintf(stderr, "%s: %zu projector frames, gain %.3g, %.2f s\n", args.out.c_str(),
                 frames.size(), options.gain, seconds);
    if (args.json) {
        printJson(json.dump());
    }
}

// What `vpe render` does once its options are parsed.
void runRender(const RenderArguments& args) {
    const auto start = std::chrono::steady_clock::now();
    const auto light = scene::parsePosition(args.light, "--light");
    const SizeArgument viewSize = parseSizeArgument(args.viewSize, "--view-size", 8192);
    const int viewWidth = viewSize.width, viewHeight = viewSize.height;
    if (!(args.intensity > 0) || !std::isfinite(args.intensity)) {
        throw common::InputError("--intensity must be a positive number");
    }
    proto::BundleFile file = proto::BundleFile::open(args.bundle);
    const renderer::BundleScene bundleScene = [&] {
        try {
            return renderer::BundleScene(file.view(), args.weights);
        } catch (const std::invalid_argument& error) {
            throw common::InputError(std::string("--weights: ") + error.what());
        }
    }();
    const proto::Vec3d viewer = viewerOf(args, bundleScene);
    const renderer::VirtualLight virtualLight = virtualLightOf(args, light);
    // --viewer draws for that one eye; without it, as the device draws the bundle.
    const renderer::RenderScene scene = args.viewer.empty()
                                            ? bundleScene.scene(virtualLight)
                                            : bundleScene.scene(virtualLight, viewer);
    renderer::RenderOptions options;
    options.threads = static_cast<int>(common::resolveThreadCount(args.threads));
    options.gain = static_cast<double>(file.view().settings().gain);
    if (!args.gain.empty() && args.gain != "auto") {
        options.gain = parseGain(args.gain);
    }
    renderer::ProjectorFrame frame = renderer::renderProjectorFrame(scene, options);
    if (args.gain == "auto") {
        options.gain = renderer::gainForClippedFraction(frame, args.clipTarget);
        frame = renderer::renderProjectorFrame(scene, options);
    }
    const int w = frame.level.width, h = frame.level.height;
    image::writeImage8(args.out, w, h, 3, levelPicture(frame.level));
    if (!args.exr.empty()) {
        image::writeImage(args.exr, w, h, 3, frame.level.values, image::PixelFormat::kFloat);
    }
    nlohmann::json json;
    json["bundle"] = args.bundle;
    json["preset"] = bundleScene.presetName();
    json["width"] = w;
    json["height"] = h;
    json["gain"] = frame.stats.gain;
    json["covered_pixels"] = frame.stats.coveredPixels;
    json["clipped_fraction"] = frame.stats.clippedFraction;
    json["clipped_high_pixels"] = frame.stats.clippedHighPixels;
    json["clipped_low_pixels"] = frame.stats.clippedLowPixels;
    if (!args.simulate.empty() || !args.direct.empty()) {
        const proto::PinholeCamera camera = proto::cameraLookingAt(
            viewWidth, viewHeight, args.fov, viewer, meshCentre(file.view().mesh()));
        const renderer::DirectView direct = renderer::renderDirectView(scene, camera, options);
        const renderer::SimulatedView simulated =
            renderer::simulateVisitorView(scene, frame.level, camera, options);
        const double exposure = args.exposure > 0 ? args.exposure : autoExposure(direct);
        if (!args.simulate.empty()) {
            image::writeImage8(args.simulate, viewWidth, viewHeight, 3,
                               srgbPicture(simulated.radiance, exposure));
        }
        if (!args.direct.empty()) {
            image::writeImage8(args.direct, viewWidth, viewHeight, 3,
                               srgbPicture(direct.radiance, exposure));
        }
        const renderer::LoopClosure loop = renderer::compareVisitorViews(frame, simulated, direct);
        json["exposure"] = exposure;
        json["loop"] = {{"seen_pixels", loop.seenPixels},
                        {"compared_pixels", loop.comparedPixels},
                        {"shadowed_pixels", loop.shadowedPixels},
                        {"mean_relative_error", loop.meanRelativeError},
                        {"p99_relative_error", loop.p99RelativeError},
                        {"max_relative_error", loop.maxRelativeError},
                        {"psnr", loop.psnr}};
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json["seconds"] = seconds;
    std::fprintf(stderr,
                 "%s: %dx%d frame, gain %.3g, %.2f%% of %zu object pixels clipped, %.2f s\n",
                 args.out.c_str(), w, h, frame.stats.gain, 100.0 * frame.stats.clippedFraction,
                 frame.stats.coveredPixels, seconds);
    if (args.json) {
        printJson(json.dump());
    }
}

}  // namespace

void addRenderCommand(CLI::App& app, Action& action) {
    auto args = std::make_shared<RenderArguments>();
    CLI::App* command = app.add_subcommand(
        "render",
        "Render a bundle on the CPU: the projector frame, and previews of what a visitor sees");
    command
        ->add_option("BUNDLE", args->bundles,
                     "Device bundle (.vpeb) from vpe bake; or the bundles of a show of several "
                     "projectors (--out is then a folder, one frame each, and --simulate shows "
                     "their combined light)")
        ->required();
    command->add_option("--light", args->light, "Virtual light position x,y,z (m, object frame)")
        ->required();
    command->add_option("--intensity", args->intensity, "Virtual light irradiance")
        ->capture_default_str();
    command->add_option("--viewer", args->viewer, "Viewer position x,y,z (default: the bundle's)");
    command->add_option("--weights", args->weights, "Weight-map preset (default: the first)");
    command->add_option("--gain", args->gain,
                        "Gain on the rendered radiance, or 'auto': the largest ≤ 1 that clips at "
                        "most --clip-target of the object's pixels (default: the bundle's)");
    command->add_option("--clip-target", args->clipTarget, "Clipped share --gain auto allows")
        ->capture_default_str();
    command->add_option("--out", args->out, "Projector frame: 8-bit drive levels (PNG)")
        ->required();
    command->add_option("--exr", args->exr, "Also the drive levels as floats (OpenEXR)");
    command->add_option("--simulate", args->simulate,
                        "Preview: the white object lit by the frame, seen from the viewer (sRGB)");
    command->add_option("--direct", args->direct,
                        "Preview: the material itself on the object, seen from the viewer (sRGB)");
    command->add_option("--view-size", args->viewSize, "Preview size WxH")->capture_default_str();
    command->add_option("--view-fov", args->fov, "Preview vertical field of view (degrees)")
        ->capture_default_str();
    command->add_option("--exposure", args->exposure,
                        "Preview exposure (0: automatic, from the direct view)");
    addThreadsOption(command, args->threads);
    addJsonFlag(command, args->json);
    command->callback([args, &action] {
        action = [args] {
            if (args->bundles.size() > 1) {
                runRenderShow(*args);
            } else {
                args->bundle = args->bundles.front();
                runRender(*args);
            }
        };
    });
}

}  // namespace vpe::cli
