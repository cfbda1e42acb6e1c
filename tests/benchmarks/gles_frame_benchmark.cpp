// SPDX-License-Identifier: MIT
// GlesFrameRenderer at 1920 × 1080, M = 10, RGB, two regions (low-rank rank 12, as `vpe bake`
// writes them) with the bake's θs basis (K = 4), a plane over 90% of the pixels, headless
// (llvmpipe here). Per scene — a static preset, a preset cross-fading, two live regions blended
// per frame — the median ms per frame (render + glFinish, no readback) with the light moving
// every frame, and in the same run the pass-through floor: a shader reading exactly the same
// textures per pixel and doing nothing else (GlesFrameRenderer::renderPassThrough); frames of
// the two alternate so that both see the same load. Next to them, the scene's frame shader
// counted by vpe_shader_cost's analysis (FLOP-equivalents, texture fetches and memory bytes per
// shaded pixel; Pi 4 / Pi 5 roofline frame rates at 50% ALU efficiency, the lower of the
// operations' and the bytes' bounds).
//   vpe_gles_frame_benchmark [--texture 1024] [--frames 10] [--warmup 2] [--shaders DIR] [--json]
// --shaders writes each scene's frame shader, as compiled, to DIR/<scene>.frag. With --json,
// stdout ends with {"scenes": [{"name", "ms_per_frame", "floor_ms", "ratio", "cpu_ms",
// "flop_eq_per_pixel", "texture_fetches_per_pixel", "memory_bytes_per_pixel", "pi4_fps",
// "pi4_compute_fps", "pi4_memory_fps", "pi5_fps", ...}]}.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <GLES3/gl31.h>
#include <nlohmann/json.hpp>
#include <time.h>
#include <unistd.h>

#include "vpe/bake/bundle_writer.h"
#include "vpe/bake/theta_basis_fit.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/gles/gles_frame_renderer.h"
#include "vpe/renderer/gles/headless_egl_platform.h"

#include "benchmark_bundle.h"
#include "roofline.h"
#include "shader_analysis.h"

namespace {

namespace gles = vpe::renderer::gles;
using Clock = std::chrono::steady_clock;

constexpr int kWidth = 1920, kHeight = 1080;
constexpr int kRank = 12;
constexpr int kThetaFunctions = 4;

vpe::bake::BundleContents contents(int size) {
    vpe::bake::BundleContents c;
    // 1.368 m × 0.768 m at 1.5 m, f = 2000 px: 1824 × 1024 of the 1920 × 1080 pixels, 90%.
    c.mesh = vpe::benchmarks::planeMesh(64, 1.368f, 0.768f, -1.0f);
    c.projector = vpe::benchmarks::benchmarkProjector();
    c.settings.viewerPosition = {0.0f, 0.2f, -1.5f};
    c.settings.peakIrradiance = 2.0f;
    vpe::benchmarks::usePaperModel(c, size);
    const auto values = static_cast<std::size_t>(c.model.coefficientsPerTexel());
    const std::size_t texels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
    for (int region = 0; region < 2; ++region) {
        vpe::bake::BundleRegion entry = vpe::benchmarks::lowRankRegion(region, kRank);
        vpe::bake::CoefficientMapData& map = entry.coefficients;
        map.mean.resize(values);
        for (std::size_t i = 0; i < values; ++i) {
            map.mean[i] = i < 3 ? 0.4f : 0.05f / static_cast<float>(i / 3);
        }
        map.basis.resize(kRank * values);
        for (std::size_t i = 0; i < map.basis.size(); ++i) {
            map.basis[i] = 0.02f * std::sin(0.1f * static_cast<float>(i + 7 * region));
        }
        map.weights.resize(texels * kRank);
        for (std::size_t i = 0; i < map.weights.size(); ++i) {
            map.weights[i] = static_cast<float>((i * 2654435761u + region) % 1000) / 500.0f - 1.0f;
        }
        c.regions.push_back(std::move(entry));
    }
    c.presets.push_back(vpe::benchmarks::stripesPreset(size));
    vpe::bake::WeightPreset swapped = vpe::benchmarks::stripesPreset(size);
    swapped.name = "stripes-swapped";
    const std::size_t layer = swapped.alpha.size() / 2;
    std::swap_ranges(swapped.alpha.begin(), swapped.alpha.begin() + static_cast<long>(layer),
                     swapped.alpha.begin() + static_cast<long>(layer));
    c.presets.push_back(std::move(swapped));
    return c;
}

// The bake's θs basis for these textures: fitted on the decoded maps, as `vpe bake` does.
std::vector<float> thetaBasis(const std::filesystem::path& bundle) {
    const vpe::proto::BundleFile file = vpe::proto::BundleFile::open(bundle);
    vpe::bake::ThetaMoment moment(file->model().harmonics);
    for (const vpe::proto::RegionView& region : file->regions()) {
        moment.add(vpe::renderer::decodeCoefficientMap(region.coefficients,
                                                       file->model().coefficientsPerTexel()));
    }
    return vpe::bake::fitThetaBasis(moment, kThetaFunctions).functions;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double processCpuMs() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

// Wall time, and CPU time of the whole process (llvmpipe's threads included: it hardly depends
// on what else the machine runs).
struct FrameTime {
    double wallMs = 0;
    double cpuMs = 0;
};

template <typename Frame>
FrameTime timeFrame(Frame&& frame) {
    const auto start = Clock::now();
    const double cpuStart = processCpuMs();
    frame();
    return {std::chrono::duration<double, std::milli>(Clock::now() - start).count(),
            processCpuMs() - cpuStart};
}

struct Scene {
    const char* name;
    bool liveWeights;
    bool fading;
    bool measuredLight = false;  // format 1.4's maps (two more fetches a pixel), a curve response
    bool inverseSquare = false;  // the light falls off with distance (its own program)
    bool roomLight = false;      // the bundle's E_ambient is subtracted (its own program)
};

}  // namespace

int main(int argc, char** argv) {
    int textureSize = 1024, frames = 10, warmup = 2;
    std::string shaderFolder;
    bool json = false;
    for (int i = 1; i < argc; ++i) {
        const std::string option = argv[i];
        if (option == "--json") {
            json = true;
            continue;
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "vpe_gles_frame_benchmark: %s: missing value\n", argv[i]);
            return 2;
        }
        const char* value = argv[++i];
        if (option == "--shaders") {
            shaderFolder = value;
        } else if (option == "--texture") {
            textureSize = std::atoi(value);
        } else if (option == "--frames") {
            frames = std::atoi(value);
        } else if (option == "--warmup") {
            warmup = std::atoi(value);
        } else {
            std::fprintf(stderr, "vpe_gles_frame_benchmark: unknown option %s\n", option.c_str());
            return 2;
        }
    }
    if (textureSize < 16 || frames < 1 || warmup < 0) {
        std::fprintf(stderr,
                     "vpe_gles_frame_benchmark: --texture ≥ 16, --frames ≥ 1, --warmup ≥ 0\n");
        return 2;
    }
    const std::filesystem::path folder = std::filesystem::temp_directory_path() /
                                         ("vpe-gles-benchmark-" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder);
    int status = 0;
    nlohmann::json report;
    report["scenes"] = nlohmann::json::array();
    try {
        const std::filesystem::path path = folder / "scene.vpeb";
        vpe::bake::BundleContents bundleContents = contents(textureSize);
        vpe::bake::writeBundle(path, bundleContents);
        bundleContents.model.thetaBasis = thetaBasis(path);
        vpe::bake::writeBundle(path, bundleContents);
        const vpe::proto::BundleFile bundle =
            vpe::proto::BundleFile::open(path, {.verifyChecksum = false});
        // The same scene with the light measured on site: F and D per projector pixel, the
        // crosstalk, and the response above black as vpe bake --radiometry writes it (33 samples).
        const std::filesystem::path measuredPath = folder / "measured.vpeb";
        {
            vpe::bake::BundleContents measured = bundleContents;
            vpe::bake::BundleRadiometry radiometry;
            radiometry.mixing = {1, 0.076, 0.011, 0.068, 1, 0.057, 0.011, 0.097, 1};
            const std::size_t pixels = std::size_t{kWidth} * kHeight;
            for (std::size_t p = 0; p < pixels; ++p) {
                const float shade = 0.7f + 0.3f * static_cast<float>(p % 1931) / 1931.0f;
                for (const float f : {0.30f, 0.27f, 0.22f}) {
                    radiometry.irradiance.push_back(f * shade);
                    radiometry.floor.push_back(0.02f * f);
                }
            }
            measured.radiometry = std::move(radiometry);
            measured.settings.response.kind = vpe::proto::ResponseKind::kCurve;
            for (std::size_t c = 0; c < 3; ++c) {
                for (int i = 0; i <= 32; ++i) {
                    measured.settings.response.curve[c].push_back(
                        static_cast<float>(std::pow(i / 32.0, 2.2 + 0.2 * static_cast<double>(c))));
                }
            }
            vpe::bake::writeBundle(measuredPath, measured);
        }
        const vpe::proto::BundleFile measuredBundle =
            vpe::proto::BundleFile::open(measuredPath, {.verifyChecksum = false});
        // The same scene with room light on the plaster (the assumed-light compensation's
        // E_ambient).
        const std::filesystem::path roomPath = folder / "room.vpeb";
        {
            vpe::bake::BundleContents room = bundleContents;
            room.settings.ambientIrradiance = {0.02f, 0.02f, 0.018f};
            vpe::bake::writeBundle(roomPath, room);
        }
        const vpe::proto::BundleFile roomBundle =
            vpe::proto::BundleFile::open(roomPath, {.verifyChecksum = false});

        std::unique_ptr<gles::GraphicsPlatform> platform = gles::createHeadlessEglPlatform();
        std::unique_ptr<gles::RenderTarget> target = platform->createRenderTarget(kWidth, kHeight);
        const vpe::shader_cost::ShaderCompiler compiler;
        std::printf(
            "%s\n%dx%d, M = 10, RGB, 2 regions (low rank %d), θs basis K = %d, %d² "
            "textures; median of %d frames after %d warm-up (render + glFinish), the "
            "light moving every frame\n",
            platform->description().c_str(), kWidth, kHeight, kRank, kThetaFunctions, textureSize,
            frames, warmup);
        std::printf("%-15s %8s %7s %9s %6s %8s %9s %9s %7s %8s %8s %8s\n", "scene", "frame ms",
                    "fps", "floor ms", "ratio", "CPU ms", "flop-eq", "fetches", "bytes", "pi4 fps",
                    "pi5 fps", "load ms");
        for (const Scene scene : {Scene{"static-preset", false, false},
                                  Scene{"static-falloff", false, false, false, true},
                                  Scene{"static-room", false, false, false, false, true},
                                  Scene{"static-falloff-room", false, false, false, true, true},
                                  Scene{"fade", false, true}, Scene{"live-2-regions", true, false},
                                  Scene{"measured-light", false, false, true}}) {
            gles::GlesRendererOptions options;
            options.liveWeights = scene.liveWeights;
            options.presetFadeSeconds = 1e9;  // "fade": every timed frame is a fading one
            const auto loadStart = Clock::now();
            gles::GlesFrameRenderer renderer(scene.measuredLight ? measuredBundle.view()
                                             : scene.roomLight   ? roomBundle.view()
                                                                 : bundle.view(),
                                             options);
            const double loadMs =
                std::chrono::duration<double, std::milli>(Clock::now() - loadStart).count();
            gles::FrameInputs inputs;
            inputs.inverseSquare = scene.inverseSquare;
            inputs.referenceDistance = 1.5f;
            const auto renderFrame = [&](int i) {
                const float phi = 0.3f * static_cast<float>(i);
                inputs.lightPosition = {0.6f * std::cos(phi), 0.6f * std::sin(phi), -1.2f};
                inputs.timeSeconds = 0.001 * i;
                renderer.render(*target, inputs);
                target->present();
            };
            renderFrame(0);
            if (scene.fading) {
                renderer.selectPreset("stripes-swapped");
            }
            const std::string source =
                renderer.frameShader(renderer.nextVariant(), scene.inverseSquare);
            if (!shaderFolder.empty()) {
                std::ofstream(std::filesystem::path(shaderFolder) /
                              (std::string(scene.name) + ".frag"))
                    << source;
            }
            const vpe::shader_cost::ShaderReport cost =
                vpe::shader_cost::analyzeShader(compiler, source, scene.name);
            vpe::shader_cost::FrameWorkload workload;
            workload.shadedPixels = static_cast<double>(renderer.coveredPixels());
            const vpe::shader_cost::FrameEstimate pi4Estimate = vpe::shader_cost::estimateFrame(
                cost.perPixel, vpe::shader_cost::raspberryPi4(), workload);
            const vpe::shader_cost::FrameEstimate pi5Estimate = vpe::shader_cost::estimateFrame(
                cost.perPixel, vpe::shader_cost::raspberryPi5(), workload);
            const double pi4 = pi4Estimate.framesPerSecond, pi5 = pi5Estimate.framesPerSecond;
            std::vector<double> frameMs, cpuMs, floorMs, ratio;
            for (int i = 0; i < warmup; ++i) {
                renderFrame(1 + i);
                renderer.renderPassThrough(*target);
                target->present();
            }
            for (int i = 0; i < frames; ++i) {
                const FrameTime frame = timeFrame([&] { renderFrame(1 + warmup + i); });
                const FrameTime pass = timeFrame([&] {
                    renderer.renderPassThrough(*target);
                    target->present();
                });
                frameMs.push_back(frame.wallMs);
                cpuMs.push_back(frame.cpuMs);
                floorMs.push_back(pass.wallMs);
                ratio.push_back(frame.wallMs / pass.wallMs);
            }
            // Live weights: what a change of weights costs (the blend pass), counted and timed.
            nlohmann::json change;
            if (scene.liveWeights) {
                const vpe::shader_cost::ShaderReport blend =
                    vpe::shader_cost::analyzeShader(compiler, renderer.blendShader(), "blend");
                const vpe::shader_cost::FrameEstimate pi4Change = vpe::shader_cost::estimateFrame(
                    blend.perPixel, vpe::shader_cost::raspberryPi4(), workload);
                if (!shaderFolder.empty()) {
                    std::ofstream(std::filesystem::path(shaderFolder) / "live-blend.frag")
                        << renderer.blendShader();
                }
                std::vector<double> changeMs;
                for (int i = 0; i < std::max(frames, 3); ++i) {
                    const auto changeStart = Clock::now();
                    renderer.selectPreset(i % 2 == 0 ? "stripes-swapped" : "stripes", false);
                    glFinish();
                    changeMs.push_back(
                        std::chrono::duration<double, std::milli>(Clock::now() - changeStart)
                            .count());
                }
                change = {{"flop_eq_per_pixel", blend.perPixel.flopEquivalent()},
                          {"texture_fetches_per_pixel", blend.perPixel.textureFetches},
                          {"memory_bytes_per_pixel", blend.perPixel.memoryBytes()},
                          {"pi4_ms", 1000.0 / pi4Change.framesPerSecond},
                          {"ms", median(changeMs)}};
                std::printf(
                    "  a change of weights (the blend pass): %lld FLOP-eq., %lld fetches, "
                    "%lld bytes a pixel: %.1f ms on a Pi 4 by the roofline, %.1f ms here\n",
                    static_cast<long long>(blend.perPixel.flopEquivalent()),
                    static_cast<long long>(blend.perPixel.textureFetches),
                    static_cast<long long>(blend.perPixel.memoryBytes()),
                    1000.0 / pi4Change.framesPerSecond, median(changeMs));
            }
            const double ms = median(frameMs);
            std::printf("%-15s %8.2f %7.1f %9.2f %6.2f %8.2f %9lld %9lld %7lld %8.1f %8.1f %8.0f\n",
                        scene.name, ms, 1000.0 / ms, median(floorMs), median(ratio), median(cpuMs),
                        static_cast<long long>(cost.perPixel.flopEquivalent()),
                        static_cast<long long>(cost.perPixel.textureFetches),
                        static_cast<long long>(cost.perPixel.memoryBytes()), pi4, pi5, loadMs);
            std::fflush(stdout);
            report["scenes"].push_back(
                {{"name", scene.name},
                 {"ms_per_frame", ms},
                 {"floor_ms", median(floorMs)},
                 {"ratio", median(ratio)},
                 {"cpu_ms", median(cpuMs)},
                 {"flop_eq_per_pixel", cost.perPixel.flopEquivalent()},
                 {"flops_per_pixel", cost.perPixel.flops()},
                 {"sfu_per_pixel", cost.perPixel.sfu},
                 {"texture_fetches_per_pixel", cost.perPixel.textureFetches},
                 {"memory_read_bytes_per_pixel", cost.perPixel.memoryReadBytes},
                 {"memory_write_bytes_per_pixel", cost.perPixel.memoryWriteBytes},
                 {"memory_bytes_per_pixel", cost.perPixel.memoryBytes()},
                 {"pi4_compute_fps", pi4Estimate.computeFramesPerSecond},
                 {"pi4_memory_fps", pi4Estimate.memoryFramesPerSecond},
                 {"pi5_compute_fps", pi5Estimate.computeFramesPerSecond},
                 {"pi5_memory_fps", pi5Estimate.memoryFramesPerSecond},
                 {"shaded_pixels", renderer.coveredPixels()},
                 {"pi4_fps", pi4},
                 {"pi5_fps", pi5},
                 {"load_ms", loadMs},
                 {"geometry_ms", renderer.loadTimes().geometryMs},
                 {"material_ms", renderer.loadTimes().materialMs},
                 {"shaders_ms", renderer.loadTimes().shadersMs},
                 {"change", change}});
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_gles_frame_benchmark: %s\n", error.what());
        status = 1;
    }
    std::filesystem::remove_all(folder);
    if (json && status == 0) {
        std::printf("%s\n", report.dump().c_str());
    }
    return status;
}
