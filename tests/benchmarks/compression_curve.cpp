// SPDX-License-Identifier: MIT
// Bytes per texel against rendering accuracy for the bundle's low-rank texture codes: bakes a
// texture (vpe quilt folder + one preset, or a model file) with the full half-float encoding
// and with low-rank codes of rank 4 … 16, renders each from the viewer under several lights
// (the CPU reference's direct view), and reports the PSNR of each against the full encoding.
//   vpe_compression_curve (--quilt DIR --preset WEIGHTS | --texture MODEL.exr) [--json]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vpe/bake/scene_baker.h"
#include "vpe/proto/pinhole_camera.h"
#include "vpe/renderer/cpu/bundle_scene.h"
#include "vpe/renderer/cpu/visitor_view.h"

#include "curve_texture.h"

namespace {

using vpe::renderer::Vec3d;

std::vector<vpe::renderer::DirectView> renderViews(const std::filesystem::path& bundle) {
    const vpe::proto::BundleFile file = vpe::proto::BundleFile::open(bundle);
    const vpe::renderer::BundleScene scene(file.view(), "");
    const vpe::proto::PinholeCamera camera =
        vpe::proto::cameraLookingAt(480, 360, 12.0, scene.bundleViewer(), {0, 0.075, 0});
    std::vector<vpe::renderer::DirectView> views;
    for (const Vec3d& light : {Vec3d{0.3, 0.4, 0.6}, Vec3d{-0.4, 0.2, 0.5}, Vec3d{0.0, 0.1, 0.8},
                               Vec3d{0.5, -0.1, 0.3}}) {
        vpe::renderer::VirtualLight virtualLight;
        virtualLight.position = light;
        vpe::renderer::RenderOptions options;
        views.push_back(vpe::renderer::renderDirectView(
            scene.scene(virtualLight, scene.bundleViewer()), camera, options));
    }
    return views;
}

double psnr(const vpe::renderer::DirectView& reference, const vpe::renderer::DirectView& test) {
    double peak = 0, squared = 0;
    std::size_t count = 0;
    for (std::size_t p = 0; p < reference.coverage.values.size(); ++p) {
        if (!reference.coverage.values[p]) {
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            const std::size_t i = p * 3 + static_cast<std::size_t>(c);
            peak = std::max(peak, static_cast<double>(reference.radiance.values[i]));
            const double d =
                static_cast<double>(test.radiance.values[i] - reference.radiance.values[i]);
            squared += d * d;
            ++count;
        }
    }
    const double mse = squared / static_cast<double>(std::max<std::size_t>(count, 1));
    return mse > 0 ? 10.0 * std::log10(peak * peak / mse) : 200.0;
}

// The full bundle against low-rank ones of rank 4 to 16: bytes per texel, variance kept, PSNR.
void compressionCurve(const vpe::benchmarks::CurveArguments& arguments,
                      const vpe::benchmarks::CurveWorkFolder& work) {
    vpe::bake::BakeOptions options = arguments.options;
    options.thetaBasis = 0;  // θs rendered exactly: this curve measures the texture codes alone
    options.lowRank = false;
    const vpe::bake::BakeReport full = vpe::bake::bakeScene(options, work / "full.vpeb");
    const std::vector<vpe::renderer::DirectView> reference = renderViews(work / "full.vpeb");
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%-10s %14s %20s %14s %14s\n", "encoding", "bytes/texel", "variance kept",
                "PSNR mean", "PSNR min");
    std::printf("%-10s %14d %20s %14s %14s\n", "full", full.bytesPerTexel, "1", "(reference)", "");
    for (int rank : {4, 8, 12, 16}) {
        options.lowRank = true;
        options.rank = rank;
        const vpe::bake::BakeReport report = vpe::bake::bakeScene(options, work / "low.vpeb");
        const std::vector<vpe::renderer::DirectView> views = renderViews(work / "low.vpeb");
        double sum = 0, lowest = 1e9;
        for (std::size_t v = 0; v < views.size(); ++v) {
            const double value = psnr(reference[v], views[v]);
            sum += value;
            lowest = std::min(lowest, value);
        }
        const double mean = sum / static_cast<double>(views.size());
        std::printf("%-10s %14d %20.6f %14.2f %14.2f\n", ("rank " + std::to_string(rank)).c_str(),
                    report.bytesPerTexel, report.explainedVariance, mean, lowest);
        rows.push_back({{"rank", rank},
                        {"bytes_per_texel", report.bytesPerTexel},
                        {"explained_variance", report.explainedVariance},
                        {"psnr_mean", mean},
                        {"psnr_min", lowest}});
    }
    if (arguments.json) {
        std::printf("%s\n",
                    nlohmann::json{{"full_bytes_per_texel", full.bytesPerTexel}, {"curve", rows}}
                        .dump()
                        .c_str());
    }
}

}  // namespace

int main(int argc, char** argv) {
    return vpe::benchmarks::runCurve(argc, argv, "vpe-compression-", compressionCurve);
}
