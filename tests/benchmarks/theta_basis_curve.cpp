// SPDX-License-Identifier: MIT
// What rendering in a θs basis of K functions costs (proto/MODEL.md, "Rendering in a θs
// basis"): bakes a texture (a vpe quilt folder with one preset, or a model file) as vpe bake
// does but with no basis, fits bases of K = 1 … 8 functions to the decoded maps as the bake
// does, replaces every texel's θs part by its projection Σ_j u_j h_j — by linearity the same as
// projecting after bilinear sampling — and renders the CPU reference's projector frame under
// eight lights (two grazing, one behind the object) against the exact maps: 8-bit PSNR.
//   vpe_theta_basis_curve (--quilt DIR --preset WEIGHTS | --texture MODEL.exr) [--json]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/bake/scene_baker.h"
#include "vpe/bake/theta_basis_fit.h"
#include "vpe/proto/theta_basis.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/projector_frame.h"

#include "curve_texture.h"
#include "support/reference_lights.h"

namespace {

using vpe::renderer::Vec3d;

using vpe::testing::LevelError;
using vpe::testing::psnr;
using vpe::testing::ReferenceLight;

// --gain auto's clipping share: the exact frame's gain, used for every K.
constexpr double kClippedFraction = 0.005;

// A coefficient map with every texel's θs part (each channel) replaced by its projection onto
// the basis, Σ_j u_j h_j, as the device renders it.
std::vector<float> projectedMap(std::span<const float> map, int harmonics,
                                const vpe::proto::ThetaBasis& basis) {
    const int n = vpe::proto::thetaFunctionCount(harmonics);
    const auto perTexel = static_cast<std::size_t>(3 * vpe::proto::coefficientCount(harmonics));
    std::vector<float> projected(map.begin(), map.end());
    std::vector<double> material(
        static_cast<std::size_t>(vpe::proto::thetaMaterialSize(basis.size)));
    for (std::size_t t = 0; t < map.size() / perTexel; ++t) {
        vpe::proto::projectToThetaBasis(basis, map.data() + t * perTexel, material.data());
        for (int c = 0; c < 3; ++c) {
            for (int i = 0; i < n; ++i) {
                double value = 0;
                for (int j = 0; j < basis.size; ++j) {
                    value += material[static_cast<std::size_t>(3 * (1 + j) + c)] *
                             basis.functions[static_cast<std::size_t>(j * n + i)];
                }
                projected[t * perTexel + static_cast<std::size_t>(3 * (i + 1) + c)] =
                    static_cast<float>(value);
            }
        }
    }
    return projected;
}

std::string decibels(double value) {
    char text[32];
    std::snprintf(text, sizeof text, std::isfinite(value) ? "%.1f" : "inf", value);
    return text;
}

nlohmann::json jsonDecibels(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

void thetaBasisCurve(const vpe::benchmarks::CurveArguments& arguments,
                     const vpe::benchmarks::CurveWorkFolder& work) {
    vpe::bake::BakeOptions options = arguments.options;
    options.thetaBasis = 0;  // none: the scene renders exactly, and the curve projects itself
    const auto start = std::chrono::steady_clock::now();
    const vpe::bake::BakeReport baked = vpe::bake::bakeScene(options, work / "exact.vpeb");
    const vpe::proto::BundleFile file = vpe::proto::BundleFile::open(work / "exact.vpeb");
    const vpe::renderer::BundleScene bundleScene(file.view(), "");
    const Vec3d viewer = bundleScene.bundleViewer();
    const int harmonics = baked.harmonics;

    // The maps as rendered (half floats and low-rank codes decoded), and their θs moment.
    std::vector<std::vector<float>> exactMaps;
    vpe::bake::ThetaMoment moment(harmonics);
    for (const vpe::renderer::MaterialRegion& region :
         bundleScene.scene({}, viewer).material.regions) {
        exactMaps.emplace_back(region.coefficients.begin(), region.coefficients.end());
        moment.add(exactMaps.back());
    }

    std::printf("%s: %d region%s of %dx%d, M = %d; projector %u x %u\n",
                (work / "exact.vpeb").c_str(), baked.regions, baked.regions == 1 ? "" : "s",
                baked.textureWidth, baked.textureHeight, harmonics, file->projector().width,
                file->projector().height);
    nlohmann::json lightsJson = nlohmann::json::array();
    std::vector<vpe::renderer::ProjectorFrame> exactFrames;
    std::vector<double> gains;
    std::printf("%-8s %-20s %7s %7s %18s\n", "light", "position (m)", "gain", "lit",
                "of which grazing");
    for (const ReferenceLight& light : vpe::testing::referenceLights()) {
        vpe::renderer::VirtualLight virtualLight;
        virtualLight.position = light.position;
        const vpe::renderer::RenderScene scene = bundleScene.scene(virtualLight, viewer);
        vpe::renderer::RenderOptions render;
        vpe::renderer::ProjectorFrame frame = vpe::renderer::renderProjectorFrame(scene, render);
        render.gain = vpe::renderer::gainForClippedFraction(frame, kClippedFraction);
        if (render.gain < 1) {
            frame = vpe::renderer::renderProjectorFrame(scene, render);
        }
        const vpe::testing::GrazingShare share =
            vpe::testing::grazingShare(file.view(), light.position);
        char position[64];
        std::snprintf(position, sizeof position, "(%.2f, %.2f, %.2f)", light.position.x,
                      light.position.y, light.position.z);
        std::printf("%-8s %-20s %7.3f %6.1f%% %17.1f%%\n", light.name, position, render.gain,
                    100.0 * share.lit, 100.0 * share.grazing);
        lightsJson.push_back({{"name", light.name},
                              {"position", {light.position.x, light.position.y, light.position.z}},
                              {"gain", render.gain},
                              {"lit_share", share.lit},
                              {"grazing_share_of_lit", share.grazing},
                              {"covered_pixels", frame.stats.coveredPixels}});
        gains.push_back(render.gain);
        exactFrames.push_back(std::move(frame));
    }

    std::printf("\n%-5s %12s %8s %8s %8s %8s", "K", "energy kept", "worst", "pooled", "frame",
                "linear");
    for (const ReferenceLight& light : vpe::testing::referenceLights()) {
        std::printf(" %7s", light.name);
    }
    std::printf("\n");
    nlohmann::json rows = nlohmann::json::array();
    for (const int size : {1, 2, 3, 4, 5, 6, 8, 0}) {
        vpe::proto::ThetaBasis basis = vpe::proto::ThetaBasis::full(harmonics);
        double energyKept = 1;
        if (size > 0) {
            const vpe::bake::ThetaBasisFit fit = vpe::bake::fitThetaBasis(moment, size);
            basis = vpe::proto::ThetaBasis::orthonormal(harmonics, fit.functions);
            energyKept = fit.energyKept;
        }
        std::vector<std::vector<float>> maps;
        for (const std::vector<float>& map : exactMaps) {
            maps.push_back(projectedMap(map, harmonics, basis));
        }
        const double inf = std::numeric_limits<double>::infinity();
        std::vector<double> perLight;
        double worst = inf, worstFrame = inf, worstLinear = inf;
        LevelError pooled;
        const auto lights = vpe::testing::referenceLights();
        for (std::size_t l = 0; l < lights.size(); ++l) {
            vpe::renderer::VirtualLight virtualLight;
            virtualLight.position = lights[l].position;
            vpe::renderer::RenderScene scene = bundleScene.scene(virtualLight, viewer);
            for (std::size_t r = 0; r < maps.size(); ++r) {
                scene.material.regions[r].coefficients = maps[r];
            }
            vpe::renderer::RenderOptions render;
            render.gain = gains[l];
            const LevelError error = vpe::testing::levelError(
                exactFrames[l], vpe::renderer::renderProjectorFrame(scene, render).level.values);
            perLight.push_back(psnr(error.squared8, error.count, 255.0));
            worst = std::min(worst, perLight.back());
            worstFrame = std::min(worstFrame, psnr(error.squared8Frame, error.frameCount, 255.0));
            worstLinear = std::min(worstLinear, psnr(error.squaredLevels, error.count, 1.0));
            pooled.squared8 += error.squared8;
            pooled.count += error.count;
        }
        const double pooledPsnr = psnr(pooled.squared8, pooled.count, 255.0);
        const std::string name = size > 0 ? std::to_string(size) : "full";
        std::printf("%-5s %12.6f %8s %8s %8s %8s", name.c_str(), energyKept,
                    decibels(worst).c_str(), decibels(pooledPsnr).c_str(),
                    decibels(worstFrame).c_str(), decibels(worstLinear).c_str());
        nlohmann::json perLightJson = nlohmann::json::array();
        for (const double value : perLight) {
            std::printf(" %7s", decibels(value).c_str());
            perLightJson.push_back(jsonDecibels(value));
        }
        std::printf("\n");
        std::fflush(stdout);
        rows.push_back({{"theta_basis", size > 0 ? nlohmann::json(size) : nlohmann::json("full")},
                        {"energy_kept", energyKept},
                        {"psnr_worst", jsonDecibels(worst)},
                        {"psnr_pooled", jsonDecibels(pooledPsnr)},
                        {"psnr_frame_worst", jsonDecibels(worstFrame)},
                        {"psnr_linear_worst", jsonDecibels(worstLinear)},
                        {"psnr_per_light", perLightJson}});
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "8-bit PSNR (dB) of the projector frame against the exact maps' at the exact frame's "
        "gain: on the object's pixels (worst light, all lights pooled, each light), in the "
        "whole frame (worst light), and of the levels before quantization (peak 1, worst "
        "light); %.0f s\n",
        seconds);
    if (arguments.json) {
        std::printf("%s\n", nlohmann::json{{"harmonics", harmonics},
                                           {"texture_width", baked.textureWidth},
                                           {"texture_height", baked.textureHeight},
                                           {"regions", baked.regions},
                                           {"lights", lightsJson},
                                           {"curve", rows},
                                           {"seconds", seconds}}
                                .dump()
                                .c_str());
    }
}

}  // namespace

int main(int argc, char** argv) {
    return vpe::benchmarks::runCurve(argc, argv, "vpe-theta-basis-", thetaBasisCurve);
}
